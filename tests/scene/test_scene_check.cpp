// The scene check (scene/scene_check.h, ausbau-scene-check): each finding on
// a small scene built for it, none on a clean scene or the shipped demo
// scene, and the executable's exit codes and JSON.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "geometry/primitives.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "scene/scene_check.h"
#include "test_scenes.h"
#include "workflow/installed_check.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Severity = SceneFinding::Severity;

// A folder with S (s.obj) and D (d.obj) and a scene.yaml whose body is
// `keys` (everything after format/static/dynamic).
struct SceneFiles {
  fs::path dir;
  fs::path yaml;
};

// S: a plate 100 x 100 x 5 mm under the origin. D: a 10 mm cube standing on
// it with a corner at the origin. Both shifted by `offset`.
SceneFiles WriteScene(const std::string& keys, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero(),
                      double scale = 1.0) {
  SceneFiles files;
  files.dir = testing::MakeTempDir("scene-check");
  SaveObj(MakeBox(scale * Eigen::Vector3d(-50, -50, -5) + offset, scale * Eigen::Vector3d(50, 50, 0) + offset),
          files.dir / "s.obj");
  SaveObj(MakeBox(offset, scale * Eigen::Vector3d(10, 10, 10) + offset), files.dir / "d.obj");
  files.yaml = files.dir / "scene.yaml";
  std::ofstream(files.yaml) << "format: ausbau-scene/1\nstatic: [s.obj]\ndynamic: d.obj\n" << keys;
  return files;
}

SceneSummary Check(const SceneFiles& files) { return CheckScene(LoadScene(files.yaml)); }

const SceneFinding* Find(const SceneSummary& summary, const std::string& code) {
  for (const auto& finding : summary.findings) {
    if (finding.code == code) return &finding;
  }
  return nullptr;
}

std::string Codes(const SceneSummary& summary) {
  std::string codes;
  for (const auto& finding : summary.findings) {
    codes += std::string(SeverityName(finding.severity)) + " " + finding.code + "\n";
  }
  return codes;
}

// The finding is there, with this severity, and its message names `fragment`.
void ExpectFinding(const SceneSummary& summary, const std::string& code, Severity severity,
                   const std::string& fragment = "") {
  const SceneFinding* finding = Find(summary, code);
  ASSERT_NE(finding, nullptr) << code << " missing; found:\n" << Codes(summary);
  EXPECT_EQ(finding->severity, severity) << code;
  EXPECT_NE(finding->message.find(fragment), std::string::npos) << finding->message;
  EXPECT_EQ(finding->message.find('\n'), std::string::npos) << "not one line: " << finding->message;
}

// ---------------------------------------------- at the installed pose
// (workflow/installed_check.h): measured, as the planning stages classify.

SceneSummary CheckInstalled(const TriangleMesh& d, const TriangleMesh& s) {
  const fs::path dir = testing::MakeTempDir("scene-check-installed");
  SaveObj(d, dir / "d.obj");
  SaveObj(s, dir / "s.obj");
  std::ofstream(dir / "scene.yaml") << "format: ausbau-scene/1\nunits: mm\nstatic: [s.obj]\ndynamic: d.obj\n";
  const Scene scene = LoadScene(dir / "scene.yaml");
  SceneSummary summary = CheckScene(scene);
  for (const SceneFinding& finding : CheckInstalledPose(scene, {})) summary.findings.push_back(finding);
  return summary;
}

TEST(SceneCheck, AtTheInstalledPoseACapOverlappingItsPostIsAFit) {
  // A cap (bore radius 4) on a post of radius 4.3: 0.3 mm of overlap all
  // round, as a CAD export of a press fit has (docs/rigid-exact.md).
  const TriangleMesh cap = MakeSolidOfRevolution({{0, 8}, {4, 8}, {4, 0}, {6, 0}, {6, 10}, {0, 10}}, 64);
  const TriangleMesh post = MakeSolidOfRevolution({{0, -5}, {4.3, -5}, {4.3, 7}, {0, 7}}, 64);
  const SceneSummary summary = CheckInstalled(cap, post);
  ExpectFinding(summary, "installed-fit", Severity::kWarning, "D overlaps s.obj by 0.3");
  EXPECT_EQ(Find(summary, "installed-clash"), nullptr) << Codes(summary);
}

TEST(SceneCheck, AtTheInstalledPoseAFitFinerThanThePlannersStepIsSaid) {
  // A 10 mm square peg, 30 long, in a square hole 57 um wider on each side
  // (the hole: four blocks around it).
  const double c = 0.057;
  TriangleMesh plate = MakeBox({-40, -40, 0}, {-5 - c, 40, 10});
  plate.Append(MakeBox({5 + c, -40, 0}, {40, 40, 10}));
  plate.Append(MakeBox({-5 - c, -40, 0}, {5 + c, -5 - c, 10}));
  plate.Append(MakeBox({-5 - c, 5 + c, 0}, {5 + c, 40, 10}));
  const SceneSummary summary = CheckInstalled(MakeBox({-5, -5, -10}, {5, 5, 20}), plate);
  ExpectFinding(summary, "fit-finer-than-step", Severity::kWarning, "D is 0.057 mm from S");
  // With 2 mm on each side it is not said.
  TriangleMesh wide = MakeBox({-40, -40, 0}, {-7, 40, 10});
  wide.Append(MakeBox({7, -40, 0}, {40, 40, 10}));
  EXPECT_EQ(Find(CheckInstalled(MakeBox({-5, -5, -10}, {5, 5, 20}), wide), "fit-finer-than-step"), nullptr);
}

TEST(SceneCheck, AtTheInstalledPoseAClashAndAContactAreSaid) {
  // A block 3 mm into a wall: more than 5% of its size, no fit.
  TriangleMesh wall = MakeBox({5, -20, -2}, {20, 20, 0});
  wall.Append(MakeBox({-20, -20, -2}, {-5.5, 20, 0}));
  ExpectFinding(CheckInstalled(MakeBox({-5, -5, -10}, {8, 5, 10}), wall), "installed-clash", Severity::kWarning,
                "3 mm deep in");
  // A cube standing on a plate: contact.
  ExpectFinding(CheckInstalled(MakeBox({0, 0, 0}, {10, 10, 10}), MakeBox({-50, -50, -5}, {50, 50, 0})),
                "installed-contact", Severity::kInfo, "touches S");
}

// A bracket exported in inches into a mm scene of a car (S 2 m from the
// origin): D lies 25.4 times nearer the origin and smaller. Said as such,
// and not for the same bracket in mm.
TEST(SceneCheck, ADInOtherUnitsThanTheSceneIsSaid) {
  const fs::path dir = testing::MakeTempDir("scene-check-units");
  const Eigen::Vector3d at(2000, -800, 500);  // mm
  SaveObj(MakeBox(at - Eigen::Vector3d(300, 300, 300), at + Eigen::Vector3d(300, 300, 300)), dir / "s.obj");
  SaveObj(MakeBox((at - Eigen::Vector3d(20, 10, 5)) / 25.4, (at + Eigen::Vector3d(20, 10, 5)) / 25.4),
          dir / "inch.obj");
  SaveObj(MakeBox(at - Eigen::Vector3d(20, 10, 5), at + Eigen::Vector3d(20, 10, 5)), dir / "mm.obj");
  std::ofstream(dir / "inch.yaml") << "format: ausbau-scene/1\nunits: mm\nstatic: [s.obj]\ndynamic: inch.obj\n";
  std::ofstream(dir / "mm.yaml") << "format: ausbau-scene/1\nunits: mm\nstatic: [s.obj]\ndynamic: mm.obj\n";
  const SceneSummary inch = CheckScene(LoadScene(dir / "inch.yaml"));
  ExpectFinding(inch, "units-d-mismatch", Severity::kWarning,
                "D's mesh is probably in inches while the scene says 'mm'");
  EXPECT_EQ(Find(inch, "start-far-from-s"), nullptr) << Codes(inch);
  const SceneSummary mm = CheckScene(LoadScene(dir / "mm.yaml"));
  EXPECT_EQ(Find(mm, "units-d-mismatch"), nullptr) << Codes(mm);
  EXPECT_EQ(mm.WarningCount(), 0) << Codes(mm);
  // The same bracket in metres (numbers 1000 times smaller) in a mm scene.
  SaveObj(MakeBox((at - Eigen::Vector3d(20, 10, 5)) / 1000, (at + Eigen::Vector3d(20, 10, 5)) / 1000), dir / "m.obj");
  std::ofstream(dir / "m.yaml") << "format: ausbau-scene/1\nunits: mm\nstatic: [s.obj]\ndynamic: m.obj\n";
  ExpectFinding(CheckScene(LoadScene(dir / "m.yaml")), "units-d-mismatch", Severity::kWarning, "probably in metres");
}

TEST(SceneCheck, CleanSceneHasNoFindingAndTheRightNumbers) {
  const SceneSummary summary = Check(WriteScene("units: mm\n"));
  EXPECT_TRUE(summary.findings.empty()) << Codes(summary);
  EXPECT_EQ(summary.units, "mm");
  ASSERT_TRUE(summary.millimetres_per_unit.has_value());
  EXPECT_EQ(summary.dynamic.triangles, 12);
  EXPECT_EQ(summary.dynamic.vertices, 8);
  EXPECT_EQ(summary.dynamic.degenerate_triangles, 0);
  ASSERT_EQ(summary.statics.size(), 1u);
  EXPECT_EQ(summary.statics[0].triangles, 12);
  EXPECT_NE(summary.statics[0].file.find("s.obj"), std::string::npos);
  EXPECT_NEAR(summary.dynamic_mesh_box.diagonal, std::sqrt(300.0), 1e-9);
  EXPECT_TRUE(summary.dynamic_installed_box.center.isApprox(Eigen::Vector3d(5, 5, 5)));
  EXPECT_TRUE(summary.static_box.size.isApprox(Eigen::Vector3d(100, 100, 5)));
  EXPECT_EQ(summary.installed_box_gap, 0.0);      // D stands on S: the boxes touch
  EXPECT_EQ(summary.origin_to_dynamic_box, 0.0);  // the mesh origin is D's corner
  EXPECT_FALSE(summary.goal.has_value());
}

TEST(SceneCheck, UnitsMissingUnknownAndUnitless) {
  ExpectFinding(Check(WriteScene("")), "units-missing", Severity::kWarning, "no units");
  ExpectFinding(Check(WriteScene("units: furlong\n")), "units-unknown", Severity::kWarning, "furlong");
  const SceneSummary unitless = Check(WriteScene("units: unitless\n"));
  ExpectFinding(unitless, "units-unitless", Severity::kInfo);
  EXPECT_EQ(unitless.WarningCount(), 0) << Codes(unitless);
}

TEST(SceneCheck, UnitsThatDoNotFitDsSize) {
  // A 10 mm cube written in metres' numbers (0.01) but declared mm: 0.017 mm across.
  ExpectFinding(Check(WriteScene("units: mm\n", Eigen::Vector3d::Zero(), 0.001)), "units-suspect-small",
                Severity::kWarning, "0.0173205 mm");
  // The same cube declared in metres: 17 m across.
  ExpectFinding(Check(WriteScene("units: m\n")), "units-suspect-large", Severity::kWarning, "17.3205 m = 17320.5 mm");
  // The same numbers in cm (17 cm) and inches (44 cm) are plausible.
  EXPECT_EQ(Check(WriteScene("units: cm\n")).WarningCount(), 0);
  EXPECT_EQ(Check(WriteScene("units: in\n")).WarningCount(), 0);
}

TEST(SceneCheck, CarCoordinatesAreInfoOnly) {
  const SceneSummary summary = Check(WriteScene("units: mm\n", Eigen::Vector3d(2000, -800, 500)));
  ExpectFinding(summary, "car-coordinates", Severity::kInfo, "metres from the origin");
  // D's mesh origin is now 2 m from D, but the start is the identity: the CAD convention.
  ExpectFinding(summary, "mesh-origin-far-from-d", Severity::kInfo);
  EXPECT_EQ(summary.WarningCount(), 0) << Codes(summary);
}

TEST(SceneCheck, StartFarFromS) {
  const SceneSummary far = Check(WriteScene("units: mm\nstart: {t: [500, 0, 0]}\n"));
  // D's box at start: [500, 510] x [0, 10] x [0, 10]; S's box ends at x = 50: 450 mm apart.
  EXPECT_NEAR(far.installed_box_gap, 450.0, 1e-9);
  ExpectFinding(far, "start-far-from-s", Severity::kWarning, "450 mm");
  EXPECT_NE(Find(far, "start-far-from-s")->message.find("dynamic_origin"), std::string::npos);
  // With a goal the scene is a motion task: starting away from S is normal (150 mm: less than twice S's
  // diagonal of 141.5 mm)...
  const SceneSummary task = Check(WriteScene("units: mm\nstart: {t: [200, 0, 0]}\ngoal: {t: [0, 0, 0]}\n"));
  ExpectFinding(task, "start-outside-s", Severity::kInfo);
  EXPECT_EQ(task.WarningCount(), 0) << Codes(task);
  EXPECT_EQ(FarStartWarning(LoadScene(WriteScene("units: mm\nstart: {t: [200, 0, 0]}\n").yaml)), "");
  // ... but not 450 mm away, more than kFarStartFactor (2) times the larger diagonal (S's, 141.5 mm).
  const SceneFiles far_task = WriteScene("units: mm\nstart: {t: [500, 0, 0]}\ngoal: {t: [0, 0, 0]}\n");
  const SceneSummary lost = Check(far_task);
  ExpectFinding(lost, "start-far-outside-s", Severity::kWarning, "450 mm");
  EXPECT_NE(Find(lost, "start-far-outside-s")->message.find("dynamic_origin"), std::string::npos);
  EXPECT_EQ(lost.WarningCount(), 1) << Codes(lost);
  EXPECT_NE(FarStartWarning(LoadScene(far_task.yaml)).find("450 mm outside S's box"), std::string::npos);
  // ausbau-plan says so before it plans (a tenth of a second is enough to see the line).
  const auto plan = testing::RunStageCommand(
      "plan", "--scene " + far_task.yaml.string() + " --time-limit 0.1 -o " + (far_task.dir / "p.h5").string());
  EXPECT_NE(plan.output.find("D at the start pose lies 450 mm outside S's box"), std::string::npos) << plan.output;
  // Beside S, less than D's diagonal (17 mm) away: no finding.
  const SceneSummary near = Check(WriteScene("units: mm\nstart: {t: [55, 0, 0]}\n"));
  EXPECT_NEAR(near.installed_box_gap, 5.0, 1e-9);
  EXPECT_TRUE(near.findings.empty()) << Codes(near);
}

TEST(SceneCheck, StartInsideSsBoxIsInfo) {
  // S a box around D (a cage seen from far), D inside it at the start pose.
  SceneFiles cage = WriteScene("units: mm\n");
  SaveObj(MakeBox(Eigen::Vector3d(-50, -50, -5), Eigen::Vector3d(50, 50, 50)), cage.dir / "s.obj");
  const SceneSummary inside = Check(cage);
  ExpectFinding(inside, "start-inside-s-box", Severity::kInfo);
  EXPECT_EQ(inside.WarningCount(), 0) << Codes(inside);
}

TEST(SceneCheck, DynamicOriginFarFromD) {
  const SceneSummary summary = Check(WriteScene("units: mm\ndynamic_origin: [1000, 0, 0]\nstart: {t: [1000, 0, 0]}\n"));
  // D's mesh box ends at x = 10: the origin is 990 mm away, D's diagonal 17 mm.
  EXPECT_NEAR(summary.origin_to_dynamic_box, 990.0, 1e-9);
  ExpectFinding(summary, "origin-far-from-d", Severity::kWarning, "990 mm");
  EXPECT_NE(Find(summary, "origin-far-from-d")->message.find("[5, 5, 5]"), std::string::npos);  // the box centre
  // A dynamic_origin at D's centre is fine.
  const SceneSummary centred = Check(WriteScene("units: mm\ndynamic_origin: [5, 5, 5]\nstart: {t: [5, 5, 5]}\n"));
  EXPECT_TRUE(centred.findings.empty()) << Codes(centred);
}

TEST(SceneCheck, MeshOriginFarFromDWithATurnedStart) {
  // D 2 m from its mesh origin, no dynamic_origin, the start turned 1 degree about z: D swings 35 mm.
  const SceneSummary summary = Check(WriteScene(
      "units: mm\nstart: {q: [0.99996192306417198, 0, 0, 0.0087265354982988489]}\n", Eigen::Vector3d(2000, 0, 0)));
  ExpectFinding(summary, "origin-far-from-d", Severity::kWarning, "dynamic_origin");
}

TEST(SceneCheck, SameFileAsDynamicAndStatic) {
  SceneFiles files = WriteScene("");
  std::ofstream(files.yaml) << "format: ausbau-scene/1\nunits: mm\nstatic: [s.obj, d.obj]\ndynamic: d.obj\n";
  const SceneSummary summary = Check(files);
  ExpectFinding(summary, "same-file-dynamic-and-static", Severity::kWarning, "static file 2");
  // Two static files: each one's own counts, and the total.
  ASSERT_EQ(summary.statics.size(), 2u);
  EXPECT_EQ(summary.statics[0].triangles, 12);
  EXPECT_EQ(summary.statics[1].triangles, 12);
  EXPECT_EQ(summary.static_total.triangles, 24);
  EXPECT_EQ(Find(Check(WriteScene("units: mm\n")), "same-file-dynamic-and-static"), nullptr);
}

TEST(SceneCheck, MeshesWithoutAreaAndDegenerateTriangles) {
  // D: two triangles whose vertices lie on one line.
  SceneFiles flat = WriteScene("units: mm\n");
  std::ofstream(flat.dir / "d.obj") << "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n";
  ExpectFinding(Check(flat), "dynamic-no-area", Severity::kWarning, "2 triangles");
  // S the same way.
  SceneFiles flat_static = WriteScene("units: mm\n");
  std::ofstream(flat_static.dir / "s.obj") << "v 0 0 0\nv 10 0 0\nv 20 0 0\nf 1 2 3\n";
  ExpectFinding(Check(flat_static), "static-no-area", Severity::kWarning);
  // D: a cube plus one zero-area triangle (three vertices on a line).
  SceneFiles sliver = WriteScene("units: mm\n");
  TriangleMesh cube = MakeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 10, 10));
  cube.vertices.push_back(Eigen::Vector3d(2, 2, 11));
  cube.vertices.push_back(Eigen::Vector3d(4, 2, 11));
  cube.vertices.push_back(Eigen::Vector3d(6, 2, 11));
  cube.triangles.push_back({8, 9, 10});
  SaveObj(cube, sliver.dir / "d.obj");
  const SceneSummary summary = Check(sliver);
  EXPECT_EQ(summary.dynamic.triangles, 13);
  EXPECT_EQ(summary.dynamic.degenerate_triangles, 1);
  ExpectFinding(summary, "dynamic-degenerate-triangles", Severity::kInfo, "1 of 13 triangles");
  EXPECT_EQ(Find(summary, "dynamic-no-area"), nullptr);
}

TEST(SceneCheck, CountDegenerateTriangles) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 0, 2}};  // a proper one, a collinear one, a repeated vertex
  EXPECT_EQ(CountDegenerateTriangles(mesh), 2);
}

TEST(SceneCheck, ShippedDemoSceneHasNoWarning) {
  const fs::path yaml = testing::SourceDir() / "scenes" / "panel-tilt-slide-1" / "scene.yaml";
  ASSERT_TRUE(fs::exists(yaml)) << yaml;
  const SceneSummary summary = CheckScene(LoadScene(yaml));
  EXPECT_EQ(summary.WarningCount(), 0) << Codes(summary);
}

TEST(SceneCheck, JsonAndTextHoldTheSummaryAndTheFindings) {
  const SceneSummary summary = Check(WriteScene("units: mm\nstart: {t: [500, 0, 0]}\n"));
  const YAML::Node json = YAML::Load(SceneSummaryJson(summary));  // JSON is YAML
  EXPECT_EQ(json["schema"].as<std::string>(), "ausbau-scene-check");
  EXPECT_EQ(json["version"].as<int>(), 1);
  EXPECT_EQ(json["units"].as<std::string>(), "mm");
  EXPECT_EQ(json["dynamic"]["mesh"]["triangles"].as<int>(), 12);
  EXPECT_EQ(json["static"]["files"].size(), 1u);
  EXPECT_DOUBLE_EQ(json["installed_box_gap"].as<double>(), 450.0);
  EXPECT_TRUE(json["goal"].IsNull());
  EXPECT_EQ(json["start"]["t"][0].as<double>(), 500.0);
  EXPECT_EQ(json["warnings"].as<int>(), 1);
  ASSERT_EQ(json["findings"].size(), 1u);
  EXPECT_EQ(json["findings"][0]["severity"].as<std::string>(), "warning");
  EXPECT_EQ(json["findings"][0]["code"].as<std::string>(), "start-far-from-s");
  const std::string text = SceneSummaryText(summary);
  EXPECT_NE(text.find("\nwarning start-far-from-s: D at the start pose is 450 mm"), std::string::npos) << text;
}

// ---- the executable

TEST(SceneCheckStage, ExitCodesAndJson) {
  const SceneFiles clean = WriteScene("units: mm\n");
  const auto ok = testing::RunStageCommand("scene-check", "--scene " + clean.yaml.string() + " --strict");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  // The cube stands on the plate: the one finding is the measured contact.
  EXPECT_NE(ok.output.find("0 warnings, 1 info"), std::string::npos) << ok.output;
  EXPECT_NE(ok.output.find("info installed-contact: D touches S"), std::string::npos) << ok.output;
  const auto unmeasured =
      testing::RunStageCommand("scene-check", "--scene " + clean.yaml.string() + " --strict --no-installed");
  EXPECT_NE(unmeasured.output.find("0 warnings, 0 info"), std::string::npos) << unmeasured.output;

  const SceneFiles suspicious = WriteScene("units: mm\nstart: {t: [500, 0, 0]}\n");
  const auto lenient = testing::RunStageCommand("scene-check", "--scene " + suspicious.yaml.string());
  EXPECT_EQ(lenient.exit_code, 0) << lenient.output;
  EXPECT_NE(lenient.output.find("warning start-far-from-s: "), std::string::npos) << lenient.output;
  const fs::path json_file = suspicious.dir / "out" / "check.json";
  const auto strict = testing::RunStageCommand(
      "scene-check", "--scene " + suspicious.yaml.string() + " --strict --json " + json_file.string());
  EXPECT_EQ(strict.exit_code, 1) << strict.output;
  const YAML::Node json = YAML::LoadFile(json_file.string());
  EXPECT_EQ(json["schema"].as<std::string>(), "ausbau-scene-check");
  EXPECT_EQ(json["warnings"].as<int>(), 1);
  EXPECT_EQ(json["findings"][0]["code"].as<std::string>(), "start-far-from-s");

  const auto missing = testing::RunStageCommand("scene-check", "--scene " + (clean.dir / "nope.yaml").string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("ausbau-scene-check: error: "), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("file not found"), std::string::npos) << missing.output;
  const auto no_scene = testing::RunStageCommand("scene-check", "");
  EXPECT_EQ(no_scene.exit_code, 2) << no_scene.output;
}

}  // namespace
}  // namespace ausbau
