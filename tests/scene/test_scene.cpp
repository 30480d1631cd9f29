// Scene loading (scene.yaml) and mesh I/O: the shipped OMPL.app benchmark
// scenes, a generated scene written and read back, and every input error.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "collision/scene_parts.h"
#include "core/error.h"
#include "geometry/primitives.h"
#include "planning/exact_check.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// The repository root: $AUSBAU_SOURCE_DIR (set by ctest), else the folder
// above this source file (CMake compiles it by absolute path), else the
// working directory.
fs::path SourceDir() {
  const char* env = std::getenv("AUSBAU_SOURCE_DIR");
  if (env != nullptr && *env != '\0') return fs::path(env);
  const fs::path here = fs::path(__FILE__).parent_path().parent_path();
  std::error_code ec;
  if (here.is_absolute() && fs::exists(here / "CMakeLists.txt", ec)) return here;
  return fs::current_path();
}

fs::path BenchmarkDir() { return SourceDir() / ".." / "shared" / "benchmarks" / "ompl"; }

Eigen::Vector3d VertexMean(const TriangleMesh& mesh) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& v : mesh.vertices) sum += v;
  return sum / static_cast<double>(mesh.vertices.size());
}

// Loads a benchmark scene, or skips the test when the files are not there.
#define LOAD_BENCHMARK_OR_SKIP(var, file)                                  \
  const fs::path var##_path = BenchmarkDir() / (file);                     \
  if (!fs::exists(var##_path)) GTEST_SKIP() << var##_path << " not found"; \
  const Scene var = LoadScene(var##_path)

void ExpectCentroidIsOrigin(const Scene& scene) {
  ASSERT_TRUE(scene.dynamic_origin_given);
  const Eigen::Vector3d mean = VertexMean(scene.dynamic_mesh);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(mean[a], scene.dynamic_origin[a], 1e-3) << "axis " << a << " of " << scene.file;
  }
}

TEST(BenchmarkScenes, Easy) {
  LOAD_BENCHMARK_OR_SKIP(scene, "Easy.yaml");
  EXPECT_EQ(scene.name, "Easy");
  EXPECT_EQ(scene.units, "unitless");
  ASSERT_EQ(scene.static_files.size(), 1u);
  EXPECT_EQ(scene.static_files[0].filename(), "Easy_env.dae");
  EXPECT_EQ(scene.dynamic_file.filename(), "Easy_robot.dae");
  EXPECT_EQ(scene.dynamic_mesh.triangles.size(), 56u);
  EXPECT_EQ(scene.static_mesh.triangles.size(), 176u);
  ExpectCentroidIsOrigin(scene);
  EXPECT_EQ(scene.start.t, Eigen::Vector3d(270, 160, -200));
  EXPECT_NEAR(scene.start.q.w(), 1.0, 1e-15);
  ASSERT_TRUE(scene.goal.has_value());
  EXPECT_EQ(scene.goal->t, Eigen::Vector3d(270, 160, -400));
  ASSERT_TRUE(scene.bounds.has_value());
  EXPECT_EQ(scene.bounds->min.y(), -24.25);
  EXPECT_EQ(scene.bounds->max.y(), 321.25);
}

TEST(BenchmarkScenes, Alpha15) {
  LOAD_BENCHMARK_OR_SKIP(scene, "alpha-1.5.yaml");
  EXPECT_EQ(scene.name, "alpha-1.5");
  EXPECT_EQ(scene.dynamic_mesh.triangles.size(), 2016u);
  EXPECT_EQ(scene.static_mesh.triangles.size(), 2016u);
  EXPECT_EQ(scene.dynamic_mesh.vertices.size(), 10248u);  // as OMPL.app counts them
  ExpectCentroidIsOrigin(scene);
  EXPECT_NEAR(scene.dynamic_origin.x(), -21.9097, 1e-4);
  EXPECT_NEAR(scene.dynamic_origin.y(), -11.1070, 1e-4);
  EXPECT_NEAR(scene.dynamic_origin.z(), -14.1355, 1e-4);
}

TEST(BenchmarkScenes, Apartment) {
  LOAD_BENCHMARK_OR_SKIP(scene, "Apartment.yaml");
  EXPECT_EQ(scene.dynamic_mesh.vertices.size(), 4338u);
  ExpectCentroidIsOrigin(scene);
  EXPECT_NEAR(scene.start.q.norm(), 1.0, 1e-12);
  EXPECT_NEAR(scene.start.q.z(), -0.99996192306417198, 1e-12);
}

// ----------------------------------------------------------------- fixture

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("ausbau_test_scene_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    SaveObj(MakeBox({-10, -10, -1}, {10, 10, 0}), dir_ / "env.obj");
    SaveObj(MakeBox({-0.5, -0.5, 0.25}, {0.5, 0.5, 1.5}), dir_ / "robot.obj");
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path Write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }

  // A valid scene with `extra` appended (a later key may override nothing:
  // duplicate keys are errors, so callers add only keys absent here).
  fs::path WriteScene(const std::string& extra, const std::string& dynamic = "robot.obj") const {
    return Write("scene.yaml", "format: ausbau-scene/1\nstatic: [env.obj]\ndynamic: " + dynamic + "\n" + extra);
  }

  // Expects fn to throw InputError whose message contains every string of
  // `parts`; returns the message.
  static std::string ExpectInputError(const std::function<void()>& fn, std::initializer_list<std::string> parts) {
    try {
      fn();
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
      for (const auto& part : parts) {
        EXPECT_NE(msg.find(part), std::string::npos) << "'" << part << "' not in: " << msg;
      }
      return msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "expected InputError, got: " << e.what();
      return "";
    }
    ADD_FAILURE() << "expected InputError, nothing thrown";
    return "";
  }

  std::string ExpectSceneError(const fs::path& scene, std::initializer_list<std::string> parts) {
    const std::string msg = ExpectInputError([&] { LoadScene(scene); }, parts);
    EXPECT_NE(msg.find(scene.string()), std::string::npos) << "scene file not named: " << msg;
    return msg;
  }

  fs::path dir_;
};

// ----------------------------------------------------------------- valid scenes

TEST_F(SceneFiles, GeneratedSceneRoundTrips) {
  Scene scene;
  scene.name = "box: in \"box\"";  // needs quoting
  scene.units = "mm";
  const TriangleMesh second = MakeBox({20, 20, 0}, {21, 22, 23});
  SaveObj(second, dir_ / "second env.obj");
  scene.static_files = {dir_ / "env.obj", dir_ / "second env.obj"};
  scene.dynamic_file = dir_ / "robot.obj";
  scene.dynamic_origin = {0.1, -0.2, 1.0 / 3.0};
  scene.dynamic_origin_given = true;
  scene.start.t = {1.5, 2.25, -3.125};
  scene.start.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  Pose goal;
  goal.t = {0.1, 0.2, 1e-7};
  goal.q = Eigen::Quaterniond(0, 0, 0, 1);
  scene.goal = goal;
  Aabb bounds;
  bounds.min = {-20, -20, -5};
  bounds.max = {20, 20, 1e3};
  scene.bounds = bounds;

  const fs::path yaml = dir_ / "generated.yaml";
  SaveSceneYaml(scene, yaml);
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }

  const Scene back = LoadScene(yaml);
  EXPECT_EQ(back.file, yaml);
  EXPECT_EQ(back.name, scene.name);
  EXPECT_EQ(back.units, "mm");
  ASSERT_EQ(back.static_files.size(), 2u);
  EXPECT_TRUE(fs::equivalent(back.static_files[0], scene.static_files[0]));
  EXPECT_TRUE(fs::equivalent(back.static_files[1], scene.static_files[1]));
  EXPECT_TRUE(fs::equivalent(back.dynamic_file, scene.dynamic_file));
  EXPECT_TRUE(back.dynamic_origin_given);
  EXPECT_EQ(back.dynamic_origin, scene.dynamic_origin);  // full precision
  EXPECT_EQ(back.start.t, scene.start.t);
  EXPECT_TRUE(back.start.q.isApprox(scene.start.q, 1e-15));
  ASSERT_TRUE(back.goal.has_value());
  EXPECT_EQ(back.goal->t, goal.t);
  EXPECT_TRUE(back.goal->q.isApprox(goal.q, 1e-15));
  ASSERT_TRUE(back.bounds.has_value());
  EXPECT_EQ(back.bounds->min, bounds.min);
  EXPECT_EQ(back.bounds->max, bounds.max);

  // Meshes: two boxes merged for S, one box for D; the box coordinates are
  // exact in assimp's single precision.
  EXPECT_EQ(back.static_mesh.triangles.size(), 24u);
  EXPECT_EQ(back.dynamic_mesh.triangles.size(), 12u);
  EXPECT_EQ(back.dynamic_mesh.Bounds().min, Eigen::Vector3d(-0.5, -0.5, 0.25));
  EXPECT_EQ(back.dynamic_mesh.Bounds().max, Eigen::Vector3d(0.5, 0.5, 1.5));
  EXPECT_EQ(back.static_mesh.Bounds().min, Eigen::Vector3d(-10, -10, -1));
  EXPECT_EQ(back.static_mesh.Bounds().max, Eigen::Vector3d(21, 22, 23));
  for (const auto& tri : back.static_mesh.triangles) {
    for (int i : tri) {
      EXPECT_GE(i, 0);
      EXPECT_LT(i, static_cast<int>(back.static_mesh.vertices.size()));
    }
  }
  // Each triangle of S knows its static file: the first 12 are env.obj's.
  ASSERT_EQ(back.static_part_names, (std::vector<std::string>{"env.obj", "second env.obj"}));
  ASSERT_EQ(back.static_part_of_triangle.size(), 24u);
  for (int t = 0; t < 24; ++t) EXPECT_EQ(back.static_part_of_triangle[t], t < 12 ? 0 : 1) << t;
}

TEST_F(SceneFiles, DefaultsAndComments) {
  const fs::path yaml = Write("minimal.yaml",
                              "# a comment\n"
                              "format: ausbau-scene/1   # trailing comment\n"
                              "static: env.obj\n"
                              "dynamic: robot.obj\n"
                              "start: {q: [1.0005, 0, 0, 0]}  # renormalized\n"
                              "goal: {t: [1, 2, 3]}\n");
  const Scene scene = LoadScene(yaml);
  EXPECT_EQ(scene.name, "minimal");
  EXPECT_EQ(scene.units, "");
  ASSERT_EQ(scene.static_files.size(), 1u);
  EXPECT_EQ(scene.static_files[0], dir_ / "env.obj");
  EXPECT_FALSE(scene.dynamic_origin_given);
  EXPECT_EQ(scene.dynamic_origin, Eigen::Vector3d::Zero());
  EXPECT_EQ(scene.start.t, Eigen::Vector3d::Zero());
  EXPECT_NEAR(scene.start.q.norm(), 1.0, 1e-15);
  ASSERT_TRUE(scene.goal.has_value());
  EXPECT_EQ(scene.goal->t, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(scene.goal->q.isApprox(Eigen::Quaterniond::Identity()));
  EXPECT_FALSE(scene.bounds.has_value());
  EXPECT_EQ(scene.static_mesh.triangles.size(), 12u);
}

TEST_F(SceneFiles, SaveObjRoundTripsThroughLoadMesh) {
  const TriangleMesh box = MakeBox({1, 2, 3}, {4, 5, 6});
  SaveObj(box, dir_ / "box.obj");
  const TriangleMesh back = LoadMesh(dir_ / "box.obj");
  EXPECT_EQ(back.triangles.size(), 12u);
  EXPECT_EQ(back.vertices.size(), 8u);
  EXPECT_EQ(back.Bounds().min, box.Bounds().min);
  EXPECT_EQ(back.Bounds().max, box.Bounds().max);
  // A missing folder is created; a folder that cannot exist (its parent is
  // a file) is an error that names the file.
  EXPECT_NO_THROW(SaveObj(box, dir_ / "new dir" / "box.obj"));
  EXPECT_THROW(SaveObj(box, dir_ / "box.obj" / "box.obj"), std::exception);
}

// The mesh cache (mesh_io.h MeshCacheDir): a file of 1 MiB or more is
// parsed once; the entry gives back exactly the same MeshFile, a damaged
// entry is noticed and rewritten, an edited file gets an entry of its own,
// and without AUSBAU_MESH_CACHE nothing is written.
TEST_F(SceneFiles, MeshCacheGivesBackTheParsedFileAndCatchesDamage) {
  TriangleMesh many;
  for (int k = 0; k < 4000; ++k) {
    const TriangleMesh box = MakeBox({k * 1.1, 0.3 * k, 0.7}, {k * 1.1 + 1, 0.3 * k + 1.25, 2.1});
    const int first = static_cast<int>(many.vertices.size());
    many.vertices.insert(many.vertices.end(), box.vertices.begin(), box.vertices.end());
    for (const auto& t : box.triangles) many.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
  }
  const fs::path file = dir_ / "many.obj";
  SaveObj(many, file);
  ASSERT_GE(fs::file_size(file), std::uintmax_t{1} << 20);
  const fs::path cache = dir_ / "cache";
  const auto entries = [&] {
    std::vector<fs::path> found;
    if (fs::exists(cache))
      for (const auto& e : fs::directory_iterator(cache)) found.push_back(e.path());
    return found;
  };
  const auto expect_same = [&](const MeshFile& a, const MeshFile& b) {
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (std::size_t n = 0; n < a.nodes.size(); ++n) {
      EXPECT_EQ(a.nodes[n].name, b.nodes[n].name);
      EXPECT_EQ(a.nodes[n].mesh.vertices, b.nodes[n].mesh.vertices);
      EXPECT_EQ(a.nodes[n].mesh.triangles, b.nodes[n].mesh.triangles);
    }
    EXPECT_EQ(a.parts, b.parts);
  };

  ::unsetenv("AUSBAU_MESH_CACHE");
  const MeshFile parsed = LoadMeshFile(file);
  EXPECT_TRUE(entries().empty());

  ::setenv("AUSBAU_MESH_CACHE", cache.c_str(), 1);
  expect_same(LoadMeshFile(file), parsed);  // parsed, entry written
  ASSERT_EQ(entries().size(), 1u);
  const fs::path entry = entries()[0];
  expect_same(LoadMeshFile(file), parsed);  // from the entry

  // One byte of the vertices changed: the payload hash no longer matches.
  {
    std::fstream f(entry, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(entry) / 2));
    f.put('\x7f');
  }
  const std::uintmax_t damaged_size = fs::file_size(entry);
  expect_same(LoadMeshFile(file), parsed);
  expect_same(LoadMeshFile(file), parsed);  // the rewritten entry
  EXPECT_EQ(fs::file_size(entry), damaged_size);
  // A truncated entry too.
  fs::resize_file(entry, 100);
  expect_same(LoadMeshFile(file), parsed);

  // An edited file is another key: its own entry, its own geometry.
  many.vertices[0].x() -= 0.5;
  SaveObj(many, file);
  const MeshFile edited = LoadMeshFile(file);
  EXPECT_EQ(entries().size(), 2u);
  EXPECT_EQ(edited.nodes[0].mesh.vertices[0].x(), parsed.nodes[0].mesh.vertices[0].x() - 0.5);
  ::unsetenv("AUSBAU_MESH_CACHE");
}

// ----------------------------------------------------------------- errors

TEST_F(SceneFiles, MissingSceneFile) { ExpectSceneError(dir_ / "absent.yaml", {"absent.yaml", "file not found"}); }

TEST_F(SceneFiles, YamlSyntaxError) {
  const fs::path yaml = WriteScene("start: {t: [1, 2, 3]\n");
  ExpectSceneError(yaml, {"scene.yaml", "YAML syntax error", "line"});
}

TEST_F(SceneFiles, UnknownTopLevelKey) {
  const fs::path yaml = WriteScene("# comment\nfoo: 3\n");
  ExpectSceneError(yaml, {"scene.yaml", "unknown key", "foo", "line 5"});
}

TEST_F(SceneFiles, UnknownKeyInsidePose) {
  const fs::path yaml = WriteScene("start:\n  t: [1, 2, 3]\n  qq: [1, 0, 0, 0]\n");
  ExpectSceneError(yaml, {"scene.yaml", "unknown key", "qq", "line 6"});
}

TEST_F(SceneFiles, UnknownKeyInsideBounds) {
  const fs::path yaml = WriteScene("bounds: {min: [0, 0, 0], max: [1, 1, 1], mid: [0, 0, 0]}\n");
  ExpectSceneError(yaml, {"scene.yaml", "unknown key", "mid", "line 4"});
}

TEST_F(SceneFiles, WrongFormat) {
  const fs::path yaml = Write("scene.yaml", "format: ausbau-scene/3\nstatic: env.obj\ndynamic: robot.obj\n");
  ExpectSceneError(yaml, {"unsupported format 'ausbau-scene/3'", "expected ausbau-scene/1 or ausbau-scene/2"});
}

TEST_F(SceneFiles, MissingFormat) {
  const fs::path yaml = Write("scene.yaml", "static: env.obj\ndynamic: robot.obj\n");
  ExpectSceneError(yaml, {"missing required key 'format'"});
}

TEST_F(SceneFiles, MissingDynamic) {
  const fs::path yaml = Write("scene.yaml", "format: ausbau-scene/1\nstatic: env.obj\n");
  ExpectSceneError(yaml, {"missing required key 'dynamic'"});
}

TEST_F(SceneFiles, EmptyStaticList) {
  const fs::path yaml = Write("scene.yaml", "format: ausbau-scene/1\nstatic: []\ndynamic: robot.obj\n");
  ExpectSceneError(yaml, {"static", "non-empty list"});
}

TEST_F(SceneFiles, MissingMeshFile) {
  const fs::path yaml = WriteScene("", "nothere.obj");
  ExpectSceneError(yaml, {"nothere.obj", "file not found"});
  ExpectInputError([&] { LoadMesh(dir_ / "nothere.obj"); }, {"nothere.obj", "file not found"});
}

TEST_F(SceneFiles, UnparsableMesh) {
  Write("garbage.dae", "<COLLADA><broken\n");
  const fs::path yaml = WriteScene("", "garbage.dae");
  ExpectSceneError(yaml, {"garbage.dae", "cannot read mesh (", "malformed XML"});
}

TEST_F(SceneFiles, MeshWithoutTriangles) {
  Write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  const fs::path yaml = WriteScene("", "points.obj");
  ExpectSceneError(yaml, {"points.obj", "mesh has no triangles"});
}

TEST_F(SceneFiles, MeshWithNanVertex) {
  Write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
  const fs::path yaml = WriteScene("", "nan.obj");
  ExpectSceneError(yaml, {"nan.obj", "vertex 1 is not finite", "nan"});
}

TEST_F(SceneFiles, MeshWithInfiniteVertex) {
  Write("inf.obj", "v 1e999 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ExpectInputError([&] { LoadMesh(dir_ / "inf.obj"); }, {"inf.obj", "vertex 0 is not finite (inf, 0, 0)"});
}

TEST_F(SceneFiles, QuaternionWithThreeNumbers) {
  const fs::path yaml = WriteScene("goal: {q: [1, 0, 0]}\n");
  ExpectSceneError(yaml, {"goal.q", "list of 4"});
}

TEST_F(SceneFiles, NonUnitQuaternion) {
  const fs::path yaml = WriteScene("goal: {q: [1.7, 0, 0, 0]}\n");
  ExpectSceneError(yaml, {"goal.q is not a unit quaternion", "norm 1.7"});
}

TEST_F(SceneFiles, NonFiniteQuaternion) {
  const fs::path yaml = WriteScene("start: {q: [.nan, 0, 0, 0]}\n");
  ExpectSceneError(yaml, {"start.q", "list of 4"});
}

TEST_F(SceneFiles, BoundsMinAboveMax) {
  const fs::path yaml = WriteScene("bounds: {min: [0, 0, 5], max: [1, 1, 1]}\n");
  ExpectSceneError(yaml, {"bounds.min > bounds.max", "axis z"});
}

TEST_F(SceneFiles, TranslationWithString) {
  const fs::path yaml = WriteScene("start: {t: [1, abc, 3]}\n");
  ExpectSceneError(yaml, {"start.t must be a list of 3", "abc"});
}

TEST_F(SceneFiles, DynamicOriginWrongLength) {
  const fs::path yaml = WriteScene("dynamic_origin: [1, 2]\n");
  ExpectSceneError(yaml, {"dynamic_origin must be a list of 3"});
}

TEST_F(SceneFiles, FitInterferenceIsADepthInMillimetres) {
  // Read, kept through SaveSceneYaml, and refused when it is not a depth.
  Scene scene = LoadScene(WriteScene("units: cm\nfit_interference: 0.25\n"));
  ASSERT_TRUE(scene.fit_interference_mm.has_value());
  EXPECT_EQ(*scene.fit_interference_mm, 0.25);
  EXPECT_NEAR(SceneFitRule(scene).max_depth, 0.025, 1e-15);         // in the scene's cm
  EXPECT_LT(SceneFitRule(LoadScene(WriteScene(""))).max_depth, 0);  // absent: the default rule
  const fs::path yaml = dir_ / "saved.yaml";
  SaveSceneYaml(scene, yaml);
  EXPECT_EQ(LoadScene(yaml).fit_interference_mm, scene.fit_interference_mm);
  ExpectSceneError(WriteScene("fit_interference: -1\n"), {"fit_interference must be a depth in mm >= 0", "-1"});
  ExpectSceneError(WriteScene("fit_interference: deep\n"), {"fit_interference must be a depth", "deep"});
}

TEST_F(SceneFiles, FitInterferenceDecidesTheExactCheck) {
  // D pressed 0.07 mm into the floor at its start (1 mm^2 of it): a fit by
  // the default rule, so lifting it out passes; `fit_interference: 0`
  // makes every installed interference a clash.
  const std::string start = "units: mm\nstart: {t: [0, 0, -0.32]}\n";
  Pose lifted;
  lifted.t = {0, 0, 5};
  Pose installed;
  installed.t = {0, 0, -0.32};
  const Scene fit = LoadScene(WriteScene(start));
  EXPECT_TRUE(ExactCheckPath(fit, {installed, lifted}, 0.05).valid);
  const Scene none = LoadScene(WriteScene(start + "fit_interference: 0\n"));
  const ExactCheckReport clash = ExactCheckPath(none, {installed, lifted}, 0.05);
  EXPECT_FALSE(clash.valid);
  EXPECT_NE(clash.reason.find("installed"), std::string::npos) << clash.reason;
}

TEST_F(SceneFiles, UpAxisIsReadKeptAndChecked) {
  // Absent: from the data (OBJ here: the CAD convention, z up).
  const Scene plain = LoadScene(WriteScene(""));
  EXPECT_EQ(plain.up_axis, "");
  EXPECT_EQ(SceneUpAxis(plain).axis, "z");
  EXPECT_EQ(SceneUpAxis(plain).source, "default for OBJ/STL/STEP data");
  // Given: the key wins, "+y" reads as "y", and SaveSceneYaml keeps it.
  for (const auto& [written, axis] : std::vector<std::pair<std::string, std::string>>{
           {"x", "x"}, {"y", "y"}, {"z", "z"}, {"-x", "-x"}, {"-y", "-y"}, {"-z", "-z"}, {"+y", "y"}}) {
    const Scene scene = LoadScene(WriteScene("up_axis: " + written + "\n"));
    EXPECT_EQ(scene.up_axis, axis) << written;
    EXPECT_EQ(SceneUpAxis(scene).axis, axis) << written;
    EXPECT_EQ(SceneUpAxis(scene).source, "scene key") << written;
    const fs::path saved = dir_ / "saved.yaml";
    SaveSceneYaml(scene, saved);
    EXPECT_EQ(LoadScene(saved).up_axis, axis) << written;
  }
  // Anything else is an InputError naming the key.
  for (const char* bad : {"up", "Z", "zz", "[0, 0, 1]", "1", "\"\""}) {
    ExpectSceneError(WriteScene(std::string("up_axis: ") + bad + "\n"),
                     {"scene.yaml", "up_axis must be one of x, y, z, -x, -y, -z", "line 4"});
  }
  ExpectSceneError(WriteScene("up_axes: z\n"), {"unknown key 'up_axes'", "did you mean 'up_axis'"});
}

// A COLLADA triangle with the given <up_axis> and its third vertex on that axis.
std::string ColladaTriangle(const std::string& up_axis) {
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>)" +
         up_axis + R"(</up_axis></asset>
  <library_geometries><geometry id="tri"><mesh>
    <source id="pos"><float_array id="pos-array" count="9">0 0 0 1 0 0 0 0 1</float_array>
      <technique_common><accessor source="#pos-array" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="vtx"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#vtx" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n" name="tri"><instance_geometry url="#tri"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)";
}

TEST_F(SceneFiles, UpAxisDefaultsFromTheMeshFiles) {
  // COLLADA is y-up as the scene reads it, whatever its <up_axis>: assimp
  // turns a Z_UP file's z into y on import (the vertex on z lands on y).
  Write("zup.dae", ColladaTriangle("Z_UP"));
  Write("yup.dae", ColladaTriangle("Y_UP"));
  const TriangleMesh zup = LoadMesh(dir_ / "zup.dae");
  ASSERT_EQ(zup.vertices.size(), 3u);
  bool on_y = false;
  for (const auto& v : zup.vertices) on_y = on_y || (std::abs(v.y() - 1) < 1e-9 && std::abs(v.z()) < 1e-9);
  EXPECT_TRUE(on_y) << "assimp did not rotate the Z_UP file to Y-up";

  const auto up_of = [&](const std::string& statics, const std::string& dynamic) {
    return SceneUpAxis(LoadScene(
        Write("scene.yaml", "format: ausbau-scene/1\nstatic: [" + statics + "]\ndynamic: " + dynamic + "\n")));
  };
  EXPECT_EQ(up_of("yup.dae", "zup.dae").axis, "y");
  EXPECT_EQ(up_of("yup.dae", "zup.dae").source, "default for glTF/COLLADA data");
  EXPECT_EQ(up_of("yup.dae, env.obj", "zup.dae").axis, "z");  // one OBJ: the CAD convention
  EXPECT_EQ(up_of("yup.dae", "robot.obj").axis, "z");
  Write("box.stl",
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
        "endfacet\nendsolid t\n");
  EXPECT_EQ(up_of("box.stl", "robot.obj").source, "default for OBJ/STL/STEP data");
}

TEST_F(SceneFiles, DuplicateKey) {
  const fs::path yaml = WriteScene("dynamic: robot.obj\n");
  ExpectSceneError(yaml, {"duplicate key 'dynamic'", "line 4"});
}

}  // namespace
}  // namespace ausbau
