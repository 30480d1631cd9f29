// Assembly input (format ausbau-scene/2, issue 18): parts picked by name and
// index from one multi-object OBJ written here, static entries with poses
// and units checked against hand-computed vertices, the errors (unknown
// part, D and S the same geometry, bad pose, units), and ausbau-assembly
// end to end with ausbau-scene-check and ausbau-plan on one of its scenes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/hash.h"
#include "geometry/primitives.h"
#include "scene/assembly.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "scene/scene_parts.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// A multi-object OBJ: one `o name` block per part (vertex indices global, 1-based).
void WriteObjParts(const fs::path& path, const std::vector<std::pair<std::string, TriangleMesh>>& parts) {
  std::ofstream out(path);
  out.precision(17);
  int offset = 1;
  for (const auto& [name, mesh] : parts) {
    out << "o " << name << "\n";
    for (const auto& v : mesh.vertices) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const auto& t : mesh.triangles) {
      out << "f " << t[0] + offset << " " << t[1] + offset << " " << t[2] + offset << "\n";
    }
    offset += static_cast<int>(mesh.vertices.size());
  }
}

// A base plate, a post standing on it and a cap on the post: touching at
// the assembled pose, the cap removable upwards.
const TriangleMesh kBase = MakeBox({0, 0, 0}, {10, 10, 1});
const TriangleMesh kPost = MakeBox({4, 4, 1}, {6, 6, 5});
const TriangleMesh kCap = MakeBox({3, 3, 5}, {7, 7, 6});

class AssemblyInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir("assembly");
    WriteObjParts(dir_ / "parts.obj", {{"base", kBase}, {"post", kPost}, {"cap", kCap}});
    SaveObj(MakeBox({0, 0, 0}, {1, 1, 1}), dir_ / "unit.obj");
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  fs::path Write(const std::string& text, const std::string& name = "scene.yaml") const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  static std::string ExpectError(const fs::path& scene, std::initializer_list<std::string> parts) {
    try {
      LoadScene(scene);
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_NE(message.find(scene.string()), std::string::npos) << message;
      for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
      return message;
    }
    ADD_FAILURE() << "no InputError for " << scene;
    return "";
  }
  fs::path dir_;
};

void ExpectBox(const TriangleMesh& mesh, const Eigen::Vector3d& min, const Eigen::Vector3d& max, double tol = 1e-12) {
  const Aabb box = mesh.Bounds();
  EXPECT_TRUE(box.min.isApprox(min, tol) || (box.min - min).norm() < tol) << box.min.transpose();
  EXPECT_TRUE(box.max.isApprox(max, tol) || (box.max - max).norm() < tol) << box.max.transpose();
}

TEST_F(AssemblyInput, PartsOfAnObjInFileOrder) {
  const MeshFile file = LoadMeshFile(dir_ / "parts.obj");
  ASSERT_EQ(file.parts.size(), 3u);
  EXPECT_EQ(file.Part(0).name, "base");
  EXPECT_EQ(file.Part(1).name, "post");
  EXPECT_EQ(file.Part(2).name, "cap");
  EXPECT_EQ(file.Part(1).mesh.triangles.size(), 12u);
  EXPECT_EQ(PartListText(file), "0 base, 1 post, 2 cap");
  // Node by node, then merged: exactly LoadMesh's mesh.
  const TriangleMesh whole = LoadMesh(dir_ / "parts.obj");
  const TriangleMesh merged = file.Merged();
  EXPECT_EQ(merged.vertices, whole.vertices);
  EXPECT_EQ(merged.triangles, whole.triangles);
}

TEST(PickParts, NameThenGroupThenMeshName) {
  MeshFile file;
  const auto add = [&](const std::string& name, std::vector<std::string> groups, std::vector<std::string> meshes) {
    MeshPart part;
    part.name = name;
    part.groups = std::move(groups);
    part.mesh_names = std::move(meshes);
    part.mesh = MakeBox({0, 0, 0}, {1, 1, 1});
    file.parts.push_back(static_cast<int>(file.nodes.size()));
    file.nodes.push_back(part);
  };
  add("wheel", {"root", "axle"}, {"tyre"});
  add("hub", {"root", "axle"}, {"rim"});
  add("", {"root"}, {""});
  add("wheel", {"root"}, {"tyre2"});
  const auto pick = [&](std::vector<PartPick> picks) { return PickParts(file, picks); };
  EXPECT_EQ(pick({{-1, "wheel"}}), (std::vector<int>{0, 3}));  // every part of that name
  EXPECT_EQ(pick({{-1, "axle"}}), (std::vector<int>{0, 1}));   // a group: the parts below it
  EXPECT_EQ(pick({{-1, "rim"}}), (std::vector<int>{1}));       // a mesh's name
  EXPECT_EQ(pick({{2, ""}, {-1, "hub"}, {2, ""}}), (std::vector<int>{1, 2}));
  try {
    pick({{-1, "spoke"}});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "part 'spoke' not found (parts: 0 wheel, 1 hub, 2 (unnamed), 3 wheel)");
  }
  try {
    pick({{4, ""}});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("part 4 is out of range (the file has 4 parts"), std::string::npos);
  }
}

TEST_F(AssemblyInput, DynamicByNameOrIndexAndSTheRest) {
  for (const std::string part : {"post", "1"}) {
    const Scene scene =
        LoadScene(Write("format: ausbau-scene/2\nunits: mm\nassembly: parts.obj\ndynamic: {part: " + part + "}\n"));
    EXPECT_EQ(scene.format_version, 2);
    ExpectBox(scene.dynamic_mesh, {4, 4, 1}, {6, 6, 5});
    ASSERT_EQ(scene.static_files.size(), 1u);  // the rest of the assembly
    EXPECT_EQ(scene.static_files[0], dir_ / "parts.obj");
    EXPECT_EQ(scene.dynamic_file, dir_ / "parts.obj");
    ASSERT_EQ(scene.static_mesh.triangles.size(), 24u);
    ExpectBox(scene.static_mesh, {0, 0, 0}, {10, 10, 6});
    EXPECT_EQ(scene.static_part_names, (std::vector<std::string>{"base", "cap"}));  // the product tree's
    ASSERT_EQ(scene.static_part_of_triangle.size(), 24u);
    for (int t = 0; t < 24; ++t) EXPECT_EQ(scene.static_part_of_triangle[t], t < 12 ? 0 : 1);
    EXPECT_EQ(scene.static_part_entry, (std::vector<int>{0, 0}));
  }
  // A quoted "1" is a name, not an index.
  ExpectError(Write("format: ausbau-scene/2\nassembly: parts.obj\ndynamic: {part: \"1\"}\n"),
              {"dynamic: parts.obj: part '1' not found (parts: 0 base, 1 post, 2 cap)"});
}

TEST_F(AssemblyInput, AssemblyWithoutAndExtraStatics) {
  const Scene scene =
      LoadScene(Write("format: ausbau-scene/2\nassembly: {file: parts.obj, without: cap}\nstatic: [unit.obj]\n"
                      "dynamic: {part: post}\n"));
  // static[0] = unit.obj, then the rest (the base only).
  ASSERT_EQ(scene.static_files.size(), 2u);
  EXPECT_EQ(scene.static_part_names, (std::vector<std::string>{"unit.obj", "base"}));
  EXPECT_EQ(scene.static_mesh.triangles.size(), 24u);
  ExpectBox(scene.static_mesh, {0, 0, 0}, {10, 10, 1});
  // Everything left out: S would be empty.
  ExpectError(Write("format: ausbau-scene/2\nassembly: {file: parts.obj, without: [base, cap]}\n"
                    "dynamic: {part: post}\n"),
              {"assembly: parts.obj: no part is left for S"});
  ExpectError(Write("format: ausbau-scene/2\nassembly: {file: parts.obj, without: lid}\ndynamic: {part: post}\n"),
              {"assembly.without: parts.obj: part 'lid' not found"});
}

TEST_F(AssemblyInput, StaticEntriesWithPoses) {
  // unit.obj is [0,1]^3. Entry 0: turned 90 degrees about z, then moved by
  // (10, 0, 0): (x, y, z) -> (10 - y, x, z). Entry 1: moved by (0, 0, 5).
  const double h = std::sqrt(0.5);
  const Scene scene =
      LoadScene(Write("format: ausbau-scene/2\nstatic:\n  - {file: unit.obj, pose: {t: [10, 0, 0], q: [" +
                      std::to_string(h) + ", 0, 0, " + std::to_string(h) +
                      "]}}\n  - {file: unit.obj, pose: {t: [0, 0, 5]}}\ndynamic: parts.obj\n"
                      "start: {t: [100, 0, 0]}\n"));
  const TriangleMesh unit = LoadMesh(dir_ / "unit.obj");
  ASSERT_EQ(scene.static_mesh.vertices.size(), 2 * unit.vertices.size());
  for (std::size_t i = 0; i < unit.vertices.size(); ++i) {
    const Eigen::Vector3d& v = unit.vertices[i];
    const Eigen::Vector3d turned(10 - v.y(), v.x(), v.z());
    EXPECT_LT((scene.static_mesh.vertices[i] - turned).norm(), 1e-6) << i;
    EXPECT_EQ(scene.static_mesh.vertices[unit.vertices.size() + i], v + Eigen::Vector3d(0, 0, 5)) << i;
  }
  EXPECT_EQ(scene.static_part_names, (std::vector<std::string>{"unit.obj", "unit.obj"}));
  EXPECT_EQ(scene.static_part_entry, (std::vector<int>{0, 1}));
  // D is the whole parts.obj file (a /1-style string in /2).
  EXPECT_EQ(scene.dynamic_mesh.triangles.size(), 36u);

  // Bad poses: the entry and the key are named.
  ExpectError(
      Write("format: ausbau-scene/2\nstatic: [{file: unit.obj, pose: {q: [1, 1, 0, 0]}}]\ndynamic: parts.obj\n"),
      {"static[0].pose.q is not a unit quaternion"});
  ExpectError(Write("format: ausbau-scene/2\nstatic: [{file: unit.obj, pose: {t: [1, 2]}}]\ndynamic: parts.obj\n"),
              {"static[0].pose.t must be a list of 3 finite numbers"});
  ExpectError(Write("format: ausbau-scene/2\nstatic: [{file: unit.obj, pose: [1, 2, 3]}]\ndynamic: parts.obj\n"),
              {"static[0].pose must be a mapping"});
  ExpectError(Write("format: ausbau-scene/2\nstatic: [{file: unit.obj, scale: 2}]\ndynamic: parts.obj\n"),
              {"unknown key 'static[0].scale'"});
  ExpectError(Write("format: ausbau-scene/2\nstatic: [{part: base}]\ndynamic: parts.obj\n"),
              {"static[0] needs file: (or an assembly: to pick parts from)"});
  // Format /1 knows none of it.
  ExpectError(Write("format: ausbau-scene/1\nstatic: [{file: unit.obj}]\ndynamic: parts.obj\n"),
              {"static[0] must be a non-empty string"});
  ExpectError(Write("format: ausbau-scene/1\nassembly: parts.obj\ndynamic: parts.obj\n"), {"unknown key 'assembly'"});
}

TEST_F(AssemblyInput, UnitsConvertedIntoTheScenesUnits) {
  // The scene in cm; unit.obj's 1 is 1 mm (0.1 cm) or 1 inch (2.54 cm); D in m.
  const Scene scene =
      LoadScene(Write("format: ausbau-scene/2\nunits: cm\nstatic:\n  - {file: unit.obj, units: mm}\n"
                      "  - {file: unit.obj, units: inch, pose: {t: [10, 0, 0]}}\n  - {file: unit.obj, units: cm}\n"
                      "dynamic: {file: parts.obj, part: post, units: m}\n"));
  const std::size_t n = scene.static_mesh.vertices.size() / 3;
  Aabb mm, inch, cm;
  for (std::size_t i = 0; i < n; ++i) {
    mm.Extend(scene.static_mesh.vertices[i]);
    inch.Extend(scene.static_mesh.vertices[n + i]);
    cm.Extend(scene.static_mesh.vertices[2 * n + i]);
  }
  EXPECT_NEAR(mm.max.x(), 0.1, 1e-15);
  EXPECT_NEAR(inch.min.x(), 10, 1e-15);  // scaled first, then placed
  EXPECT_NEAR(inch.max.x(), 12.54, 1e-12);
  EXPECT_EQ(cm.max, Eigen::Vector3d(1, 1, 1));  // same units: untouched
  ExpectBox(scene.dynamic_mesh, {400, 400, 100}, {600, 600, 500});
  EXPECT_EQ(scene.static_sources[1].units, "inch");
  EXPECT_DOUBLE_EQ(scene.static_sources[1].scale, 2.54);

  // An entry's units need the scene's as a length; /2 accepts only units it knows.
  ExpectError(Write("format: ausbau-scene/2\nstatic: [{file: unit.obj, units: mm}]\ndynamic: parts.obj\n"),
              {"static[0].units: converting from mm needs the scene's units as a length", "not given"});
  ExpectError(Write("format: ausbau-scene/2\nunits: unitless\nstatic: [{file: unit.obj, units: mm}]\n"
                    "dynamic: parts.obj\n"),
              {"got 'unitless'"});
  ExpectError(Write("format: ausbau-scene/2\nunits: mm\nstatic: [{file: unit.obj, units: furlong}]\n"
                    "dynamic: parts.obj\n"),
              {"static[0].units must be mm, cm, m or inch", "furlong"});
  ExpectError(Write("format: ausbau-scene/2\nunits: furlong\nstatic: unit.obj\ndynamic: parts.obj\n"),
              {"units must be mm, cm, m, inch", "got 'furlong', line 2"});
  // /1 keeps units informative: any name loads.
  EXPECT_EQ(LoadScene(Write("format: ausbau-scene/1\nunits: furlong\nstatic: unit.obj\ndynamic: parts.obj\n")).units,
            "furlong");
}

TEST_F(AssemblyInput, DAndSTheSameGeometryIsRefused) {
  // The same part on both sides.
  ExpectError(Write("format: ausbau-scene/2\nstatic: [parts.obj]\ndynamic: {file: parts.obj, part: cap}\n"),
              {"dynamic and static[0] both take part 'cap' of parts.obj: S would hold D itself"});
  ExpectError(Write("format: ausbau-scene/2\nstatic: [{file: parts.obj, part: [base, 2]}]\n"
                    "dynamic: {file: parts.obj, part: cap}\n"),
              {"both take part 'cap' of parts.obj"});
  ExpectError(Write("format: ausbau-scene/2\nstatic: parts.obj\ndynamic: parts.obj\n"),
              {"both take the whole of parts.obj"});
  // Another file with D's triangles at D's start pose.
  WriteObjParts(dir_ / "copy.obj", {{"other", kBase}, {"cap-again", kCap}});
  ExpectError(Write("format: ausbau-scene/2\nstatic: copy.obj\ndynamic: {file: parts.obj, part: cap}\n"),
              {"D at its start pose coincides with S: 12 of D's 12 triangles are triangles of S (copy.obj:cap-again)"});
  // Moved away by the start pose, or by the static entry's pose: fine.
  EXPECT_NO_THROW(
      LoadScene(Write("format: ausbau-scene/2\nstatic: copy.obj\ndynamic: {file: parts.obj, part: cap}\n"
                      "start: {t: [0, 0, 20]}\n")));
  EXPECT_NO_THROW(
      LoadScene(Write("format: ausbau-scene/2\nstatic: [{file: parts.obj, pose: {t: [50, 0, 0]}}]\n"
                      "dynamic: {file: parts.obj, part: cap}\n")));
  // Different parts of one file: fine.
  EXPECT_NO_THROW(
      LoadScene(Write("format: ausbau-scene/2\nstatic: [{file: parts.obj, part: [base, post]}]\n"
                      "dynamic: {file: parts.obj, part: cap}\n")));
  // Format /1 reads such a scene as before (scene-check warns).
  EXPECT_NO_THROW(LoadScene(Write("format: ausbau-scene/1\nstatic: parts.obj\ndynamic: parts.obj\n")));
}

TEST(CoincidentTriangles, SameVerticesInAnyOrderWithinTheTolerance) {
  const TriangleMesh box = MakeBox({0, 0, 0}, {1, 1, 1});
  TriangleMesh turned = box;
  for (auto& t : turned.triangles) t = {t[1], t[2], t[0]};  // same triangles, other vertex order
  EXPECT_EQ(CoincidentTriangles(box, turned, {}, 1e-6).triangles, 12);
  TriangleMesh nudged = box;
  for (auto& v : nudged.vertices) v += Eigen::Vector3d(1e-9, 0, 0);
  EXPECT_EQ(CoincidentTriangles(box, nudged, {}, 1e-6).triangles, 12);
  TriangleMesh moved = box;
  for (auto& v : moved.vertices) v += Eigen::Vector3d(1e-3, 0, 0);
  EXPECT_EQ(CoincidentTriangles(box, moved, {}, 1e-6).triangles, 0);
  TriangleMesh two = MakeBox({5, 5, 5}, {6, 6, 6});
  two.Append(box);
  const Coincidence c = CoincidentTriangles(box, two, std::vector<int>(12, 0), 1e-6);
  EXPECT_EQ(c.triangles, 12);
  EXPECT_EQ(c.piece, -1);  // the matching triangles are past the labelled ones
}

TEST_F(AssemblyInput, SavedAndReadBack) {
  const Scene scene = LoadScene(
      Write("format: ausbau-scene/2\nunits: cm\nassembly: {file: parts.obj, units: mm, without: [0]}\n"
            "static: [{file: unit.obj, part: 0, pose: {t: [20, 0, 0]}, units: inch}]\ndynamic: {part: post}\n"));
  const fs::path copy = dir_ / "sub" / "copy.yaml";
  fs::create_directories(copy.parent_path());
  SaveSceneYaml(scene, copy);
  const std::string text = testing::ReadTextFile(copy);
  EXPECT_NE(text.find("format: ausbau-scene/2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("assembly: {file: \"../parts.obj\", without: 0, units: \"mm\"}\n"), std::string::npos) << text;
  EXPECT_NE(text.find("dynamic: {part: \"post\"}\n"), std::string::npos) << text;
  const Scene back = LoadScene(copy);
  EXPECT_EQ(back.static_mesh.vertices, scene.static_mesh.vertices);
  EXPECT_EQ(back.static_mesh.triangles, scene.static_mesh.triangles);
  EXPECT_EQ(back.dynamic_mesh.vertices, scene.dynamic_mesh.vertices);
  EXPECT_EQ(back.static_part_names.size(), scene.static_part_names.size());
  // A /1 scene stays /1; a file swapped by code is written as that file.
  Scene plain = LoadScene(Write("format: ausbau-scene/1\nstatic: [unit.obj]\ndynamic: parts.obj\n"));
  SaveSceneYaml(plain, dir_ / "plain.yaml");
  EXPECT_NE(testing::ReadTextFile(dir_ / "plain.yaml").find("format: ausbau-scene/1\n"), std::string::npos);
  Scene swapped = scene;
  swapped.dynamic_file = dir_ / "unit.obj";
  SaveSceneYaml(swapped, dir_ / "swapped.yaml");
  EXPECT_EQ(LoadScene(dir_ / "swapped.yaml").dynamic_mesh.triangles.size(), 12u);
}

TEST_F(AssemblyInput, TwoPartsOfOneFileNeverShareDsHash) {
  const Scene post = LoadScene(Write("format: ausbau-scene/2\nassembly: parts.obj\ndynamic: {part: post}\n", "a.yaml"));
  const Scene cap = LoadScene(Write("format: ausbau-scene/2\nassembly: parts.obj\ndynamic: {part: cap}\n", "b.yaml"));
  const Scene cap2 = LoadScene(Write("format: ausbau-scene/2\nassembly: parts.obj\ndynamic: {part: 2}\n", "c.yaml"));
  EXPECT_NE(DynamicContentHash(post), DynamicContentHash(cap));
  EXPECT_EQ(DynamicContentHash(cap), DynamicContentHash(cap2));  // the same part
  const Scene plain = LoadScene(Write("format: ausbau-scene/1\nstatic: unit.obj\ndynamic: parts.obj\n", "d.yaml"));
  EXPECT_EQ(DynamicContentHash(plain), HashFile(dir_ / "parts.obj"));  // as before /2
}

// ------------------------------------------------------------ end to end

TEST_F(AssemblyInput, AssemblyWritesOneScenePerPartThatTheStagesRead) {
  const fs::path out = dir_ / "out";
  const auto run = testing::RunStageCommand(
      "assembly", "--assembly " + (dir_ / "parts.obj").string() + " -o " + out.string() + " --units mm 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const std::string part : {"base", "post", "cap"}) {
    const fs::path yaml = out / part / "scene.yaml";
    ASSERT_TRUE(fs::exists(yaml)) << run.output;
    const std::string text = testing::ReadTextFile(yaml);
    EXPECT_NE(text.find("assembly: \"../../parts.obj\"\n"), std::string::npos) << text;
    EXPECT_NE(text.find("dynamic: {part: \"" + part + "\"}\n"), std::string::npos) << text;
    EXPECT_EQ(LoadScene(yaml).static_mesh.triangles.size(), 24u);
  }
  const std::string json = testing::ReadTextFile(out / "assembly.json");
  EXPECT_NE(json.find("\"folder\": \"cap\""), std::string::npos) << json;

  const auto list = testing::RunStageCommand("assembly", "--assembly " + (dir_ / "parts.obj").string() + " --list");
  ASSERT_EQ(list.exit_code, 0) << list.output;
  EXPECT_NE(list.output.find("2\tcap\t12\t3 3 5\t7 7 6"), std::string::npos) << list.output;

  const fs::path cap = out / "cap" / "scene.yaml";
  const auto check = testing::RunStageCommand("scene-check", "--scene " + cap.string() + " 2>&1");
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_NE(check.output.find("the assembly's rest: 2 parts"), std::string::npos) << check.output;
  // The cap comes off upwards: a path within a short time limit (touching
  // parts need the rigid tolerance: rigid-exact, what VALIDITY=auto picks).
  const auto plan =
      testing::RunStageCommand("plan", "--scene " + cap.string() + " -o " + (out / "cap" / "path.h5").string() +
                                           " --validity rigid-exact --time-limit 20 2>&1");
  EXPECT_EQ(plan.exit_code, 0) << plan.output;

  // Bad input: exit 2, one line naming the file.
  const auto single = testing::RunStageCommand(
      "assembly", "--assembly " + (dir_ / "unit.obj").string() + " -o " + (dir_ / "o2").string() + " 2>&1");
  EXPECT_EQ(single.exit_code, 2) << single.output;
  EXPECT_NE(single.output.find("unit.obj: holds 1 part"), std::string::npos) << single.output;
  const auto units = testing::RunStageCommand(
      "assembly", "--assembly " + (dir_ / "parts.obj").string() + " -o " + (dir_ / "o3").string() + " --units ft 2>&1");
  EXPECT_EQ(units.exit_code, 2) << units.output;
  const fs::path unknown = Write("format: ausbau-scene/2\nassembly: parts.obj\ndynamic: {part: lid}\n");
  const auto check_unknown = testing::RunStageCommand("scene-check", "--scene " + unknown.string() + " 2>&1");
  EXPECT_EQ(check_unknown.exit_code, 2) << check_unknown.output;
  EXPECT_NE(check_unknown.output.find("part 'lid' not found (parts: 0 base, 1 post, 2 cap)"), std::string::npos)
      << check_unknown.output;
}

}  // namespace
}  // namespace ausbau
