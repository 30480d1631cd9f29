// Hostile numbers (issue 33): scenes and environments that are valid input
// but push a number to its edge (coordinates far from the origin, a huge
// OMP_NUM_THREADS, a huge goal clearance or dynamic_origin, a tiny D, a
// path of a million waypoints, an assembly of thousands of parts) and a
// glTF buffer that is a FIFO. Each case is an end-to-end run of a real
// executable (build/bin/ausbau-*) on meshes written here, under `timeout
// -s KILL`, so that a hang fails its case and not the suite: every stage
// must keep its time limit, or refuse plainly, whatever the geometry.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <Eigen/Core>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "planning/path_io.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Outcome = testing::CommandOutcome;  // stdout and stderr together

// Runs `command` with bash in `dir`, the stages first on PATH, killed after
// `timeout_s` (exit 137).
Outcome Shell(const fs::path& dir, const std::string& command, int timeout_s) {
  return testing::RunInDir(dir, command, timeout_s);
}

void Write(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

bool Contains(const Outcome& outcome, const std::string& pattern) {
  return std::regex_search(outcome.output, std::regex(pattern));
}

// Closed axis-aligned boxes as OBJ text, each its own object, the
// coordinates written with all their digits.
class BoxesObj {
 public:
  void Add(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
    char line[160];
    text_ += "o box" + std::to_string(boxes_++) + "\n";
    for (int i = 0; i < 8; ++i) {
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", (i & 1) ? max.x() : min.x(),
                    (i & 2) ? max.y() : min.y(), (i & 4) ? max.z() : min.z());
      text_ += line;
    }
    // Outward faces (corner i: bit 0 x, bit 1 y, bit 2 z), two triangles each.
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
      std::snprintf(line, sizeof line, "f %d %d %d\nf %d %d %d\n", first_ + q[0], first_ + q[1], first_ + q[2],
                    first_ + q[0], first_ + q[2], first_ + q[3]);
      text_ += line;
    }
    first_ += 8;
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
  int boxes_ = 0, first_ = 1;
};

// A 10 mm cube in a 12 mm cavity whose only opening, in the +x wall, is
// 9.7 mm square: the cube cannot leave (its smallest cross-section is
// 10 x 10), at any tolerance below 0.15 mm. Everything moved by `offset`.
void WriteCubeInCavity(const fs::path& dir, const Eigen::Vector3d& offset) {
  BoxesObj cube, cavity;
  cube.Add(offset - Eigen::Vector3d::Constant(5), offset + Eigen::Vector3d::Constant(5));
  const double inner = 6, outer = 10, hole = 4.85;
  const auto wall = [&](Eigen::Vector3d min, Eigen::Vector3d max) { cavity.Add(offset + min, offset + max); };
  wall({-outer, -outer, -outer}, {-inner, outer, outer});  // -x
  wall({-inner, -outer, -outer}, {inner, -inner, outer});  // -y
  wall({-inner, inner, -outer}, {inner, outer, outer});    // +y
  wall({-inner, -inner, -outer}, {inner, inner, -inner});  // -z
  wall({-inner, -inner, inner}, {inner, inner, outer});    // +z
  wall({inner, -outer, -outer}, {outer, -hole, outer});    // +x, around the hole
  wall({inner, hole, -outer}, {outer, outer, outer});
  wall({inner, -hole, -outer}, {outer, hole, -hole});
  wall({inner, -hole, hole}, {outer, hole, outer});
  Write(dir / "cube.obj", cube.text());
  Write(dir / "cavity.obj", cavity.text());
  char t[200];
  std::snprintf(t, sizeof t, "[%.17g, %.17g, %.17g]", offset.x(), offset.y(), offset.z());
  Write(dir / "scene.yaml", std::string("format: ausbau-scene/1\nname: cube-in-cavity\nunits: mm\n") +
                                "static: [\"cavity.obj\"]\ndynamic: \"cube.obj\"\ndynamic_origin: " + t +
                                "\nstart: {t: " + t + ", q: [1, 0, 0, 0]}\n");
}

// ------------------------------------------------- 1. precision far away

// At the origin the cube is NOT REMOVABLE; 1e7 mm away single precision
// stores the 9.7 mm opening as 10 mm and the cube had passed ("exact check
// passed"): now the scene is refused, naming the file, before any work.
TEST(HostileNumbers, CubeInACavityFarFromTheOriginIsRefusedNotRemovable) {
  const fs::path near = testing::MakeTempDir("hostile-near");
  WriteCubeInCavity(near, Eigen::Vector3d::Zero());
  const Outcome at_origin = Shell(near, "ausbau-plan --scene scene.yaml --time-limit 2 -o p.h5", 60);
  EXPECT_EQ(at_origin.exit_code, 3) << at_origin.output;

  const fs::path far = testing::MakeTempDir("hostile-far");
  WriteCubeInCavity(far, Eigen::Vector3d::Constant(1e7));
  for (const std::string validity : {"", "--validity collision"}) {
    const Outcome outcome = Shell(far, "ausbau-plan --scene scene.yaml " + validity + " --time-limit 2 -o p.h5", 60);
    EXPECT_EQ(outcome.exit_code, 2) << validity << "\n" << outcome.output;
    EXPECT_TRUE(Contains(outcome,
                         "ausbau-plan: error: [^\n]*(cube|cavity)\\.obj: coordinates reach 1e\\+07[^\n]*"
                         "single precision[^\n]*move the model nearer the origin\n"))
        << outcome.output;
    EXPECT_FALSE(Contains(outcome, "REMOVABLE|exact check passed")) << outcome.output;
    EXPECT_FALSE(fs::exists(far / "p.h5"));
  }
}

// ------------------------------------------------- 2. OMP_NUM_THREADS

// OMP_NUM_THREADS far beyond the cores, with the default --threads 0, made
// libgomp crash (SIGSEGV); clamped now in the runner every stage shares,
// also for the stages without a scene.yaml runner (distfield-build).
TEST(HostileNumbers, AHugeOmpNumThreadsIsClampedInEveryRunner) {
  const fs::path dir = testing::MakeTempDir("hostile-omp");
  WriteCubeInCavity(dir, Eigen::Vector3d::Zero());
  const Outcome outcome = Shell(dir,
                                "export OMP_NUM_THREADS=100000; "
                                "ausbau-distfield-build --scene scene.yaml --field-cells 16 --output-dir fields && "
                                "ausbau-voxelize --scene scene.yaml --voxel-budget 20000 -o v.h5",
                                60);
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_TRUE(Contains(outcome, "ausbau-distfield-build: .*100000 threads .* more than the")) << outcome.output;
  EXPECT_TRUE(Contains(outcome, "ausbau-voxelize: .*100000 threads .* more than the")) << outcome.output;
}

// ------------------------------------------------- 3. limits kept

// Runs `command` in `dir` and expects it to end within `limit_s` plus a
// few seconds of loading and writing.
void ExpectWithinTimeLimit(const fs::path& dir, const std::string& command, double limit_s) {
  const auto start = std::chrono::steady_clock::now();
  const Outcome outcome = Shell(dir, command, 60);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(outcome.exit_code, 137) << command << "\n" << outcome.output;
  EXPECT_TRUE(outcome.exit_code == 0 || outcome.exit_code == 3) << command << "\n" << outcome.output;
  EXPECT_LT(seconds, limit_s + 8) << command << "\n" << outcome.output;
}

// goal: {clearance: 1e9} (the documented maximum) makes the bounds 1e9
// wide: one motion across them was billions of discrete steps (past an
// int) with no look at the clock, and ausbau-plan ran past --time-limit 2
// for minutes. Each motion now stops at the deadline, as if blocked. Since
// sweeps prove motions through open space at once, the planner finds the
// 1e9-long path in a moment; then the dense re-check of it (1e10 poses) ran
// for hours: it stops too, after as long again as --time-limit, and the run
// has no path (cut short).
TEST(HostileNumbers, AHugeGoalClearanceKeepsThePlannersTimeLimit) {
  const fs::path dir = testing::MakeTempDir("hostile-clearance");
  WriteCubeInCavity(dir, Eigen::Vector3d::Zero());
  BoxesObj free_cube;
  free_cube.Add(Eigen::Vector3d::Constant(-5), Eigen::Vector3d::Constant(5));
  BoxesObj block;
  block.Add(Eigen::Vector3d(20, -20, -20), Eigen::Vector3d(40, 20, 20));
  Write(dir / "cube.obj", free_cube.text());
  Write(dir / "cavity.obj", block.text());
  Write(dir / "scene.yaml",
        "format: ausbau-scene/1\nunits: mm\nstatic: [\"cavity.obj\"]\ndynamic: \"cube.obj\"\n"
        "goal: {clearance: 1e9}\n");
  ExpectWithinTimeLimit(dir, "ausbau-plan --scene scene.yaml --time-limit 2 -o p.h5", 2);
}

// A D of 1e-6 mm in the cavity: the straight pulls probe the way out in
// steps of 2% of D's diagonal (billions of them across S) without a look at
// the clock; now they stop at the deadline. (The smoother's motions take
// its deadline the same way; no tiny-D path reached it here to test.)
TEST(HostileNumbers, ATinyPartKeepsTheTimeLimits) {
  const fs::path dir = testing::MakeTempDir("hostile-tiny");
  WriteCubeInCavity(dir, Eigen::Vector3d::Zero());
  BoxesObj tiny;
  tiny.Add(Eigen::Vector3d::Constant(-5e-7), Eigen::Vector3d::Constant(5e-7));
  Write(dir / "cube.obj", tiny.text());
  ExpectWithinTimeLimit(dir, "ausbau-plan --scene scene.yaml --time-limit 2 -o p.h5", 2);
}

// A path of a million waypoints made ausbau-smooth run past 600 s and
// ausbau-report write 175 MB: path artifacts above kMaxPathWaypoints are
// refused by every reader, before any work.
TEST(HostileNumbers, APathOfAMillionWaypointsIsRefused) {
  const fs::path dir = testing::MakeTempDir("hostile-waypoints");
  WriteCubeInCavity(dir, Eigen::Vector3d::Zero());
  PathArtifact path;
  path.success = true;
  path.planner = "rrt-connect";
  path.validity = ValidityMode::kRigidExact;
  path.units = "mm";
  path.waypoints.resize(1000000);
  for (std::size_t i = 0; i < path.waypoints.size(); ++i) {
    path.waypoints[i].t = Eigen::Vector3d(1e-4 * static_cast<double>(i), 0, 0);
  }
  WritePathArtifact(dir / "big.h5", path, Provenance{"test", "0", "", {}});
  for (const std::string command : {"ausbau-smooth --scene scene.yaml --path big.h5 -o s.h5 --time-limit 5",
                                    "ausbau-verdict --scene scene.yaml --path big.h5 -o v.json",
                                    "ausbau-report --scene scene.yaml --path big.h5 -o r.html"}) {
    const auto start = std::chrono::steady_clock::now();
    const Outcome outcome = Shell(dir, command, 60);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(outcome.exit_code, 2) << command << "\n" << outcome.output;
    EXPECT_TRUE(Contains(outcome, "error: big\\.h5: holds 1000000 waypoints, more than the limit of 100000"))
        << command << "\n"
        << outcome.output;
    EXPECT_LT(seconds, 20) << command;
  }
  EXPECT_FALSE(fs::exists(dir / "s.h5"));
  EXPECT_FALSE(fs::exists(dir / "r.html"));
}

// An assembly file of many small parts (a grid of cubes, each its own OBJ
// object): ausbau-assembly loaded every scene it wrote back, reading the
// whole file once per part (2,000 parts 33 s, 10,000 past 600 s). 4,000
// parts now take a few seconds; a part given twice is still refused.
TEST(HostileNumbers, AnAssemblyOfManyPartsIsSplitInLinearTime) {
  const fs::path dir = testing::MakeTempDir("hostile-assembly");
  BoxesObj parts;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::Vector3d corner(3.0 * (i % 20), 3.0 * ((i / 20) % 20), 3.0 * (i / 400));
    parts.Add(corner, corner + Eigen::Vector3d::Constant(1));
  }
  Write(dir / "many.obj", parts.text());
  const Outcome outcome = Shell(dir, "ausbau-assembly --assembly many.obj -o out --units mm > list.txt", 40);
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_TRUE(fs::exists(dir / "out/assembly.json"));
  EXPECT_TRUE(fs::exists(dir / "out/box3999/scene.yaml"));

  // The same part twice: the second copy's scene has the first in S.
  BoxesObj twice;
  twice.Add(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1));
  twice.Add(Eigen::Vector3d::Constant(3), Eigen::Vector3d::Constant(4));
  twice.Add(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1));
  Write(dir / "twice.obj", twice.text());
  const Outcome duplicated = Shell(dir, "ausbau-assembly --assembly twice.obj -o out2", 40);
  EXPECT_EQ(duplicated.exit_code, 2) << duplicated.output;
  EXPECT_TRUE(Contains(duplicated,
                       "ausbau-assembly: error: [^\n]*out2/box0/scene\\.yaml: D at its start pose "
                       "coincides with S: 12 of D's 12 triangles are triangles of S \\(box2\\)"))
      << duplicated.output;
}

// ------------------------------------------------- 4. a FIFO among the files a reader opens

// A glTF file whose buffer uri names a FIFO blocked assimp's importer (in
// its child process) forever: files the importer opens besides the mesh
// file must be regular files too.
TEST(HostileNumbers, AGltfBufferThatIsAFifoIsRefused) {
  const fs::path dir = testing::MakeTempDir("hostile-fifo");
  WriteCubeInCavity(dir, Eigen::Vector3d::Zero());
  const std::string gltf =
      "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{\"mesh\": 0}],\n"
      " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}],\n"
      " \"buffers\": [{\"uri\": \"BUFFER\", \"byteLength\": 36}],\n"
      " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 36}],\n"
      " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\",\n"
      "   \"min\": [0, 0, 0], \"max\": [1, 1, 0]}]}\n";
  Write(dir / "part.gltf", std::regex_replace(gltf, std::regex("BUFFER"), "fifo.bin"));
  ASSERT_EQ(::mkfifo((dir / "fifo.bin").c_str(), 0644), 0);
  Write(dir / "scene.yaml", "format: ausbau-scene/1\nstatic: [\"cavity.obj\"]\ndynamic: \"part.gltf\"\n");
  const Outcome outcome = Shell(dir, "ausbau-scene-check --scene scene.yaml", 20);
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  EXPECT_TRUE(Contains(outcome,
                       "ausbau-scene-check: error: [^\n]*part\\.gltf: cannot read mesh \\(it names "
                       "'[^']*fifo\\.bin', which is not a regular file"))
      << outcome.output;
}

}  // namespace
}  // namespace ausbau
