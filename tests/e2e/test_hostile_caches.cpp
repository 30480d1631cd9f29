// Issue 33: caches that miss an input, and answers that were silently
// wrong. Each test is an end-to-end run of the real executables on a tiny
// scene written here (boxes), asserting the exit code and the message; the
// artifact cases of the same issue (links in an HDF5 artifact, a goal
// region too small to reach) are in tests/e2e/test_bad_input.cpp's table.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "collision/distance_field.h"
#include "geometry/primitives.h"
#include "scene/mesh_io.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Outcome = testing::CommandOutcome;

// Runs `command` with bash in `dir`, the stages first on PATH, stderr into
// the output; a hang is killed after `timeout_s`.
Outcome Shell(const fs::path& dir, const std::string& command, int timeout_s = 60) {
  return testing::RunInDir(dir, command, timeout_s);
}

bool Has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

void Write(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// A scene of format /1 in `dir`: S and D as the files named.
void WriteScene(const fs::path& dir, const std::string& statics, const std::string& dynamic) {
  Write(dir / "scene.yaml",
        "format: ausbau-scene/1\nname: hostile\nunits: mm\nstatic: [" + statics + "]\ndynamic: " + dynamic + "\n");
}

// The box [min, max] as a glTF 2.0 file `name`.gltf whose vertices and
// indices lie in the external buffer `name`.bin (8 float32 vertices, 36
// uint16 indices).
void WriteGltfBox(const fs::path& dir, const std::string& name, const Eigen::Vector3d& min,
                  const Eigen::Vector3d& max) {
  const TriangleMesh box = MakeBox(min, max);
  ASSERT_EQ(box.vertices.size(), 8u);
  std::string bin;
  for (const Eigen::Vector3d& v : box.vertices) {
    for (int k = 0; k < 3; ++k) {
      const float f = static_cast<float>(v[k]);
      bin.append(reinterpret_cast<const char*>(&f), sizeof f);
    }
  }
  for (const auto& triangle : box.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint16_t i = static_cast<std::uint16_t>(triangle[k]);
      bin.append(reinterpret_cast<const char*>(&i), sizeof i);
    }
  }
  const std::size_t vertex_bytes = 8 * 3 * sizeof(float), index_bytes = 3 * box.triangles.size() * 2;
  Write(dir / (name + ".bin"), bin);
  const auto number = [](double v) { return std::to_string(static_cast<float>(v)); };
  Write(dir / (name + ".gltf"),
        "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],\n"
        " \"nodes\": [{\"name\": \"" +
            name +
            "\", \"mesh\": 0}],\n"
            " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}, \"indices\": 1}]}],\n"
            " \"accessors\": [\n"
            "  {\"bufferView\": 0, \"componentType\": 5126, \"count\": 8, \"type\": \"VEC3\", \"min\": [" +
            number(min.x()) + ", " + number(min.y()) + ", " + number(min.z()) + "], \"max\": [" + number(max.x()) +
            ", " + number(max.y()) + ", " + number(max.z()) +
            "]},\n"
            "  {\"bufferView\": 1, \"componentType\": 5123, \"count\": " +
            std::to_string(3 * box.triangles.size()) +
            ", \"type\": \"SCALAR\"}],\n"
            " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": " +
            std::to_string(vertex_bytes) + "},\n  {\"buffer\": 0, \"byteOffset\": " + std::to_string(vertex_bytes) +
            ", \"byteLength\": " + std::to_string(index_bytes) +
            "}],\n"
            " \"buffers\": [{\"uri\": \"" +
            name + ".bin\", \"byteLength\": " + std::to_string(bin.size()) + "}]}\n");
}

// ---------------------------------------------------------------- class 1: caches that miss an input

// A glTF's geometry lies in its external .bin: editing the buffer alone
// (the .gltf unchanged) must change the scene's cache key, so that plan
// computes again instead of calling its old path up to date, and a path
// made before the edit is refused as made from another D.
TEST(HostileCaches, GltfExternalBufferIsInTheCacheKey) {
  const fs::path dir = testing::MakeTempDir("hostile-gltf");
  SaveObj(MakeBox({0, 0, 0}, {10, 10, 10}), dir / "env.obj");
  WriteGltfBox(dir, "part", {20, 0, 0}, {30, 10, 10});
  WriteScene(dir, "env.obj", "part.gltf");
  const std::string plan = "ausbau-plan --scene scene.yaml --time-limit 10 -o path.h5";
  const Outcome first = Shell(dir, plan);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  ASSERT_TRUE(Has(Shell(dir, plan).output, "up to date"));
  fs::copy_file(dir / "path.h5", dir / "old.h5");
  // D moved 2 mm along y in the buffer only.
  WriteGltfBox(dir, "moved", {20, 2, 0}, {30, 12, 10});
  fs::rename(dir / "moved.bin", dir / "part.bin");
  const Outcome again = Shell(dir, plan);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_FALSE(Has(again.output, "up to date")) << again.output;
  const Outcome smooth = Shell(dir, "ausbau-smooth --scene scene.yaml --path old.h5 -o smooth.h5");
  EXPECT_EQ(smooth.exit_code, 2) << smooth.output;
  EXPECT_TRUE(Has(smooth.output, "old.h5: was made from another D")) << smooth.output;
  const Outcome verdict = Shell(dir, "ausbau-verdict --scene scene.yaml --path old.h5 -o v.json");
  EXPECT_EQ(verdict.exit_code, 2) << verdict.output;
  EXPECT_TRUE(Has(verdict.output, "old.h5: was made from another D")) << verdict.output;
}

// An edited distance-field cache entry (its provenance intact, its cells
// changed) is not copied into a new run as valid: its content hash does
// not match, it is built again with a one-line note, and the cache is
// repaired.
TEST(HostileCaches, EditedDistanceFieldCacheEntryIsBuiltAgain) {
  const fs::path dir = testing::MakeTempDir("hostile-distfield");
  SaveObj(MakeBox({0, 0, 0}, {10, 10, 10}), dir / "env.obj");
  SaveObj(MakeBox({20, 0, 0}, {30, 10, 10}), dir / "part.obj");
  WriteScene(dir, "env.obj", "part.obj");
  const std::string build = "AUSBAU_CACHE_DIR=cache ausbau-distfield-build --scene scene.yaml --field-cells 16 ";
  const Outcome first = Shell(dir, build + "--output-dir a");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(dir / "cache")) entries.push_back(entry.path());
  ASSERT_EQ(entries.size(), 2u);
  for (const fs::path& entry : entries) {
    // Every nearest point moved far away: a field that says "far from S" everywhere.
    const hid_t file = H5Fopen(entry.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t set = H5Dopen2(file, "nearest_point", H5P_DEFAULT);
    ASSERT_GE(set, 0);
    const hid_t space = H5Dget_space(set);
    const hssize_t count = H5Sget_simple_extent_npoints(space);
    const std::vector<float> far(static_cast<std::size_t>(count), 1e6f);
    EXPECT_GE(H5Dwrite(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, far.data()), 0);
    H5Sclose(space);
    H5Dclose(set);
    H5Fclose(file);
  }
  const Outcome second = Shell(dir, build + "--output-dir b");
  EXPECT_EQ(second.exit_code, 0) << second.output;
  EXPECT_FALSE(Has(second.output, "copied from the cache")) << second.output;
  EXPECT_TRUE(Has(second.output, "does not match its content_hash (edited or damaged); building it again"))
      << second.output;
  for (const char* name : {"distfield-static.h5", "distfield-dynamic.h5"}) {
    EXPECT_EQ(DistanceFieldContentHash(*ReadDistanceField(dir / "b" / name)),
              DistanceFieldContentHash(*ReadDistanceField(dir / "a" / name)))
        << name;
  }
  // The cache holds good fields again.
  const Outcome third = Shell(dir, build + "--output-dir c");
  EXPECT_EQ(third.exit_code, 0) << third.output;
  EXPECT_TRUE(Has(third.output, "copied from the cache")) << third.output;
  EXPECT_FALSE(Has(third.output, "content_hash")) << third.output;
}

// Without HOME and XDG_CACHE_HOME and with a read-only scene folder the
// distance fields get no cache (a note says so), never a fixed folder in
// the system's temporary directory that every user shares.
TEST(HostileCaches, NoHomeAndAReadOnlySceneFolderMeansNoCache) {
  const fs::path dir = testing::MakeTempDir("hostile-nohome");
  const fs::path scene = dir / "scene";
  fs::create_directories(scene);
  SaveObj(MakeBox({0, 0, 0}, {10, 10, 10}), scene / "env.obj");
  SaveObj(MakeBox({20, 0, 0}, {30, 10, 10}), scene / "part.obj");
  WriteScene(scene, "env.obj", "part.obj");
  fs::permissions(scene, fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                  fs::perm_options::remove);
  const std::string bare = "env -u HOME -u XDG_CACHE_HOME -u AUSBAU_CACHE_DIR ";
  const Outcome built = Shell(dir, bare +
                                       "ausbau-distfield-build --scene scene/scene.yaml --field-cells 16 "
                                       "--output-dir out");
  EXPECT_EQ(built.exit_code, 0) << built.output;
  EXPECT_TRUE(Has(built.output,
                  "no cache for the distance fields: scene is read-only and neither XDG_CACHE_HOME "
                  "nor HOME is set"))
      << built.output;
  EXPECT_TRUE(Has(built.output, "cache none")) << built.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "distfield-static.h5"));
  EXPECT_FALSE(Has(built.output, "ausbau-cache")) << built.output;
  // Without an output folder there is nowhere to build into: said so.
  const Outcome nowhere = Shell(dir, bare + "ausbau-distfield-build --scene scene/scene.yaml --field-cells 16");
  EXPECT_EQ(nowhere.exit_code, 2) << nowhere.output;
  EXPECT_TRUE(Has(nowhere.output, "there is no cache to build the fields into")) << nowhere.output;
  fs::permissions(scene, fs::perms::owner_write, fs::perm_options::add);
}

// ---------------------------------------------------------------- class 2: silently wrong answers

// D, a plate 0.5 mm thin, closed in a cage of 3 mm walls: the only way out
// is through a wall. At --resolution 0.1 the straight pull up checks poses
// 1.4 mm apart: at each the plate is below the roof, wholly inside it
// (where FCL, which intersects surfaces only, sees nothing) or above it, so
// the planner, its certification at a quarter of that step and the dense
// re-check all passed a path 1.3 mm deep in S and ausbau-plan said 0. Then
// the exact check caught it; now the certification, at 0.25% of D's
// diagonal whatever the search's step, does (planning/certify.h), and no
// search finds a way out (again at 1% where time is left): no valid path,
// exit 3, and the verdict says NOT REMOVABLE.
TEST(WrongAnswers, CollisionValidityPathThroughAWallIsNoPath) {
  const fs::path dir = testing::MakeTempDir("hostile-wall");
  const double w = 3;  // the walls' thickness
  TriangleMesh cage = MakeBox({-58, -58, -w}, {58, 58, 0});
  cage.Append(MakeBox({-58, -58, 10}, {58, 58, 10 + w}));
  cage.Append(MakeBox({-58, -58, 0}, {-55, 58, 10}));
  cage.Append(MakeBox({55, -58, 0}, {58, 58, 10}));
  cage.Append(MakeBox({-55, -58, 0}, {55, -55, 10}));
  cage.Append(MakeBox({-55, 55, 0}, {55, 58, 10}));
  SaveObj(cage, dir / "cage.obj");
  SaveObj(MakeBox({-50, -50, 4.75}, {50, 50, 5.25}), dir / "plate.obj");
  WriteScene(dir, "cage.obj", "plate.obj");
  const Outcome plan = Shell(dir,
                             "ausbau-plan --scene scene.yaml --validity collision --resolution 0.1 --time-limit 10 "
                             "-o path.h5 --csv path.csv");
  EXPECT_EQ(plan.exit_code, 3) << plan.output;
  EXPECT_TRUE(Has(plan.output, "of the path fails the fine re-check and could not be re-planned")) << plan.output;
  EXPECT_FALSE(fs::exists(dir / "path.csv"));
  const Outcome verdict = Shell(dir, "ausbau-verdict --scene scene.yaml --path path.h5 -o v.json");
  EXPECT_EQ(verdict.exit_code, 3) << verdict.output;
  EXPECT_TRUE(Has(verdict.output, "NOT REMOVABLE")) << verdict.output;
}

// Two separate cubes 3 mm apart: either comes out first, so the order is
// one step with both, never "no order exists" with a cycle a -> b -> a.
TEST(WrongAnswers, TwoSeparateCubesComeOutInOneStep) {
  const fs::path dir = testing::MakeTempDir("hostile-cubes");
  SaveObj(MakeBox({0, 0, 0}, {10, 10, 10}), dir / "a.obj");
  SaveObj(MakeBox({13, 0, 0}, {23, 10, 10}), dir / "b.obj");
  const Outcome order = Shell(dir, "ausbau-order --part a.obj --part b.obj --part-budget 5 --output-dir order");
  EXPECT_EQ(order.exit_code, 0) << order.output;
  EXPECT_TRUE(Has(order.output, "step 1: a b")) << order.output;
  const std::string json = testing::ReadTextFile(dir / "order" / "order.json");
  EXPECT_TRUE(Has(json, "\"cycle\": null")) << json;
}

}  // namespace
}  // namespace ausbau
