// STEP assemblies (issue 31 item 1): a product tree written by OpenCASCADE
// here (tests/cad/step_fixture.h: a plate with a bore, a pin in it, a
// sub-assembly of two studs placed twice), read back by ReadStepAssembly:
// names, paths, placements, units (mm and inch), closed meshes within the
// chord error; ausbau-assembly end to end (scenes, assembly.json, --dynamic,
// the tessellation recorded) and ausbau-plan taking the pin out of its bore;
// and the bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "cad/step_assembly.h"
#include "cad/step_scenes.h"
#include "core/error.h"
#include "geometry/primitives.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "step_fixture.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

std::string PathText(const StepPart& part) {
  std::string out;
  for (const std::string& node : part.path) out += (out.empty() ? "" : "/") + node;
  return out;
}

// Every edge of a closed, consistently oriented mesh is used once in each
// direction.
bool IsClosedAndOriented(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

double Volume(const TriangleMesh& mesh) {
  double six = 0;
  for (const auto& t : mesh.triangles) {
    six += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  }
  return six / 6;
}

class StepAssemblyTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::MakeTempDir("step"); }
  fs::path dir_;
};

TEST_F(StepAssemblyTest, TheProductTreeComesBackWithNamesPlacementsAndClosedMeshes) {
  const fs::path file = dir_ / "bench.step";
  testing::WriteStepFixture(file);
  StepTessellation tessellation;
  const StepAssembly assembly = ReadStepAssembly(file, tessellation);
  ASSERT_EQ(assembly.parts.size(), 6u);
  EXPECT_EQ(assembly.products, 3);  // plate, pin, stud: each tessellated once
  std::vector<std::string> paths;
  for (const StepPart& part : assembly.parts) paths.push_back(PathText(part));
  EXPECT_EQ(paths, (std::vector<std::string>{"bench/plate", "bench/pin", "bench/pair:1/stud", "bench/pair:1/stud",
                                             "bench/pair:2/stud", "bench/pair:2/stud"}));
  // Placements multiply down the tree: the second stud of the second pair,
  // (20, 0, 0) in the pair, which is turned 90 degrees about z and placed
  // at (60, 45, 10), is at (60, 65, 10).
  EXPECT_TRUE(assembly.parts[5].placement.translation().isApprox(Eigen::Vector3d(60, 65, 10), 1e-12));
  const Aabb stud = assembly.parts[5].mesh.Bounds();
  EXPECT_NEAR(stud.min.x(), 57, tessellation.deflection_mm);
  EXPECT_NEAR(stud.max.y(), 68, tessellation.deflection_mm);
  EXPECT_NEAR(stud.max.z(), 25, 1e-9);
  const Aabb pin = assembly.parts[1].mesh.Bounds();
  EXPECT_NEAR(pin.min.z(), -5, 1e-9);
  EXPECT_NEAR(pin.max.z(), 25, 1e-9);
  for (const StepPart& part : assembly.parts) {
    EXPECT_TRUE(IsClosedAndOriented(part.mesh)) << PathText(part);
    EXPECT_EQ(part.faces_without_triangles, 0) << PathText(part);
  }
  // Volumes within the chord error: the plate 60000 - 250 pi (its bore's
  // polygon is inscribed, so a little more), the pin 750 pi (a little less).
  const double plate = Volume(assembly.parts[0].mesh), pin_volume = Volume(assembly.parts[1].mesh);
  EXPECT_GE(plate, 60000 - 250 * M_PI);
  EXPECT_LE(plate, 60000 - 250 * M_PI + 2 * M_PI * 5 * 10 * tessellation.deflection_mm);
  EXPECT_LE(pin_volume, 750 * M_PI);
  EXPECT_GE(pin_volume, 750 * M_PI - 2 * M_PI * 5 * 30 * tessellation.deflection_mm);
  // The chord error: the pin's vertices lie on its cylinder, the middle of
  // each edge at most the deflection inside it.
  const TriangleMesh& mesh = assembly.parts[1].mesh;
  double deepest = 0;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = mesh.vertices[t[k]], b = mesh.vertices[t[(k + 1) % 3]];
      for (const Eigen::Vector3d& p : {a, Eigen::Vector3d((a + b) / 2)}) {
        const double r = std::hypot(p.x() - 30, p.y() - 30);
        if (p.z() > -5 + 1e-9 && p.z() < 25 - 1e-9) deepest = std::max(deepest, 5 - r);
        EXPECT_LE(r, 5 + 1e-9);
      }
    }
  }
  EXPECT_LE(deepest, tessellation.deflection_mm + 1e-9);
  EXPECT_GT(deepest, 0);  // the check above checked something
}

TEST_F(StepAssemblyTest, AnInchFileComesBackInMillimetres) {
  const fs::path mm = dir_ / "mm.step", inch = dir_ / "inch.stp";
  testing::WriteStepFixture(mm);
  testing::StepFixtureOptions options;
  options.unit = "INCH";
  testing::WriteStepFixture(inch, options);
  const StepAssembly a = ReadStepAssembly(mm, {}), b = ReadStepAssembly(inch, {});
  EXPECT_EQ(a.file_units, "millimetre");
  EXPECT_EQ(b.file_units, "INCH");  // as the file names it
  ASSERT_EQ(a.parts.size(), b.parts.size());
  for (std::size_t k = 0; k < a.parts.size(); ++k) {
    const Aabb x = a.parts[k].mesh.Bounds(), y = b.parts[k].mesh.Bounds();
    EXPECT_TRUE(x.min.isApprox(y.min, 1e-9) && x.max.isApprox(y.max, 1e-9)) << k;
  }
}

TEST_F(StepAssemblyTest, ControlCharactersInANameDoNotReachTheTerminal) {
  // An escape sequence (C0: ESC [31m) and a C1 control (U+009B, CSI) in a
  // product's name, written raw into the STEP file: they come back as '?'.
  testing::StepFixtureOptions options;
  options.plate_name = "ev\x1b[31mil\xc2\x9bx";
  testing::WriteStepFixture(dir_ / "evil.step", options);
  const StepAssembly assembly = ReadStepAssembly(dir_ / "evil.step", {});
  const std::string& name = assembly.parts[0].name;
  EXPECT_EQ(name.substr(0, 3), "ev?") << name;
  for (std::size_t k = 0; k < name.size(); ++k) {
    const auto c = static_cast<unsigned char>(name[k]);
    EXPECT_FALSE(c < 0x20 || c == 0x7f) << name;
    if (c == 0xC2 && k + 1 < name.size()) EXPECT_GE(static_cast<unsigned char>(name[k + 1]), 0xA0) << name;
  }
  EXPECT_EQ(StepPartNames(assembly, "x.obj")[0], "ev__31mil__x");
}

TEST_F(StepAssemblyTest, NamesAreUniqueAndPicksFollowTheTree) {
  const fs::path file = dir_ / "bench.step";
  testing::WriteStepFixture(file);
  const StepAssembly assembly = ReadStepAssembly(file, {});
  const std::vector<std::string> names = StepPartNames(assembly, "bench.tessellated.obj");
  EXPECT_EQ(names, (std::vector<std::string>{"plate", "pin", "stud", "stud-2", "stud-3", "stud-4"}));
  EXPECT_EQ(PickStepParts(assembly, names, "pin"), (std::vector<int>{1}));
  EXPECT_EQ(PickStepParts(assembly, names, "stud-3"), (std::vector<int>{4}));
  EXPECT_EQ(PickStepParts(assembly, names, "bench/pair:2"), (std::vector<int>{4, 5}));
  EXPECT_EQ(PickStepParts(assembly, names, "pair:1"), (std::vector<int>{2, 3}));
  EXPECT_EQ(PickStepParts(assembly, names, "stud"), (std::vector<int>{2, 3, 4, 5}));  // its name in the file
  EXPECT_THROW(PickStepParts(assembly, names, "lid"), InputError);
}

TEST_F(StepAssemblyTest, AnInstanceNamedByNothingOfItsOwnIsNamedAfterItsProduct) {
  // OpenCASCADE's own export of dm1 (CAx-IF dm1-oc-214) names its
  // instances "1", "2", ...: its nuts and bolts were scenes "1", "2-3".
  // CATIA V5 (CAx-IF s1-c5-214) names them "*DIT33", "*DIT34": the scenes
  // were "_DIT33", "_DIT34" where the products say FOOT_FRONT_000.
  // SolidWorks names every instance after its NAUO's identifier: "NAUO7".
  for (const std::string instance : {"7", "*DIT33", "NAUO7"}) {
    const fs::path file = dir_ / "bench.step";
    testing::StepFixtureOptions options;
    options.pin_instance_name = instance;
    testing::WriteStepFixture(file, options);
    const StepAssembly assembly = ReadStepAssembly(file, {});
    EXPECT_EQ(StepPartNames(assembly, "bench.tessellated.obj")[1], "pin") << instance;
    EXPECT_EQ(PathText(assembly.parts[1]), "bench/" + instance);
  }
}

TEST_F(StepAssemblyTest, AnAssemblySplitIntoFilesIsReadWithThemFromAnyFolder) {
  // Each part in a file of its own beside the assembly's (DOCUMENT_FILE
  // references, as CAx-IF's s1 from three CAD systems). OpenCASCADE looked
  // for them in the working folder where the assembly's path is relative:
  // every part came back empty ("no triangle after tessellation").
  const fs::path folder = dir_ / "split";
  fs::create_directories(folder);
  testing::StepFixtureOptions options;
  options.external_prefix = "bench-";
  testing::WriteStepFixture(folder / "bench.step", options);
  std::string files;
  for (const auto& entry : fs::directory_iterator(folder)) files += entry.path().filename().string() + " ";
  ASSERT_NE(files.find("bench-"), std::string::npos) << files;
  const StepAssembly assembly = ReadStepAssembly(fs::relative(folder / "bench.step"), {});
  ASSERT_EQ(assembly.parts.size(), 6u);
  for (const StepPart& part : assembly.parts) EXPECT_FALSE(part.mesh.triangles.empty()) << PathText(part);
  EXPECT_EQ(StepPartNames(assembly, "bench.tessellated.obj")[1], "pin");

  // Without the other files, no scene: S would lack parts that may hold D.
  const fs::path alone = dir_ / "alone";
  fs::create_directories(alone);
  fs::copy_file(folder / "bench.step", alone / "bench.step");
  try {
    ReadStepAssembly(alone / "bench.step", {});
    ADD_FAILURE() << "read without its parts' files";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("other STEP files that could not be read"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bench-"), std::string::npos) << e.what();
  }
}

TEST_F(StepAssemblyTest, AssemblyWritesScenesWithTheTessellationAndThePinComesOut) {
  const fs::path file = dir_ / "bench.step", out = dir_ / "scenes";
  testing::WriteStepFixture(file);
  const auto run = testing::RunStageCommand(
      "assembly", "--assembly " + file.string() + " -o " + out.string() + " --dynamic pin --dynamic bench/pair:2 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(fs::exists(out / "bench.tessellated.obj"));
  for (const std::string part : {"pin", "stud-3", "stud-4"}) EXPECT_TRUE(fs::exists(out / part / "scene.yaml"));
  EXPECT_FALSE(fs::exists(out / "plate" / "scene.yaml"));
  const std::string yaml = testing::ReadTextFile(out / "pin" / "scene.yaml");
  EXPECT_NE(yaml.find("tessellation_deflection: 0.02"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("units: \"mm\""), std::string::npos) << yaml;
  const Scene scene = LoadScene(out / "pin" / "scene.yaml");
  ASSERT_TRUE(scene.tessellation_deflection_mm.has_value());
  EXPECT_EQ(*scene.tessellation_deflection_mm, 0.02);
  EXPECT_EQ(scene.static_part_names.size(), 5u);  // the plate and the four studs
  const std::string json = testing::ReadTextFile(out / "assembly.json");
  for (const std::string expected :
       {"\"format\": \"STEP\"", "\"file_units\": \"millimetre\"", "\"deflection_mm\": 0.02", "\"instances\": 6",
        "\"path\": [\"bench\", \"pair:2\", \"stud\"]", "\"file\": \"../bench.step\""}) {
    EXPECT_NE(json.find(expected), std::string::npos) << expected << "\n" << json;
  }
  // The pin sits in its bore with no clearance (one radius in CAD, one
  // polygon after tessellation: the facets coincide): it comes out along
  // its axis, and the exact check passes the written path (contact is
  // settled by mesh_depth.h's ShiftOffBound, in well under a second).
  const auto plan = testing::RunStageCommand("plan", "--scene " + (out / "pin" / "scene.yaml").string() + " -o " +
                                                         (out / "pin" / "path.h5").string() +
                                                         " --validity rigid-exact --time-limit 30 2>&1");
  EXPECT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("straight pull: D comes out along [0.0000, 0.0000, 1.0000]"), std::string::npos)
      << plan.output;
  // A tight fit: 0.03 mm of clearance, finer than the chord error.
  testing::StepFixtureOptions tight;
  tight.gap_mm = 0.03;
  testing::WriteStepFixture(dir_ / "tight.step", tight);
  const auto scenes = testing::RunStageCommand("assembly", "--assembly " + (dir_ / "tight.step").string() + " -o " +
                                                               (dir_ / "tight").string() + " --dynamic pin 2>&1");
  ASSERT_EQ(scenes.exit_code, 0) << scenes.output;
  const auto tight_plan = testing::RunStageCommand(
      "plan", "--scene " + (dir_ / "tight" / "pin" / "scene.yaml").string() + " -o " +
                  (dir_ / "tight" / "pin" / "path.h5").string() + " --validity rigid-exact --time-limit 30 2>&1");
  EXPECT_EQ(tight_plan.exit_code, 0) << tight_plan.output;
}

// make step's pipeline (pipelines/step.mk): STEP in, the picked part's
// verdict and the batch's table out, through the real executables.
TEST_F(StepAssemblyTest, StepPipelineGoesFromTheStepFileToAVerdict) {
  const fs::path file = dir_ / "bench.step", out = dir_ / "run";
  testing::WriteStepFixture(file);
  const auto run =
      testing::RunShellCommand("make --no-print-directory -f " + (testing::SourceDir() / "pipelines/step.mk").string() +
                               " BIN=" + testing::BinDir().string() + " STEP=" + file.string() +
                               " OUT=" + out.string() + " DYNAMIC=pin THREADS=1 WITH_REPORT=0 TIME_LIMIT=30 2>&1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(fs::exists(out / "scenes" / "assembly.json"));
  const std::string verdict = testing::ReadTextFile(out / "pin" / "verdict.json");
  EXPECT_NE(verdict.find("\"removable\": true"), std::string::npos) << verdict << run.output;
  EXPECT_NE(run.output.find("pin"), std::string::npos) << run.output;
}

TEST_F(StepAssemblyTest, TheSceneKeyTessellationDeflectionReadsBackAndRefusesNonsense) {
  SaveObj(MakeBox({0, 0, 0}, {1, 1, 1}), dir_ / "d.obj");
  SaveObj(MakeBox({2, 0, 0}, {3, 1, 1}), dir_ / "s.obj");
  const auto write = [&](const std::string& value) {
    std::ofstream(dir_ / "scene.yaml") << "format: ausbau-scene/1\nunits: mm\nstatic: s.obj\ndynamic: d.obj\n"
                                       << "tessellation_deflection: " << value << "\n";
    return dir_ / "scene.yaml";
  };
  Scene scene = LoadScene(write("0.05"));
  ASSERT_TRUE(scene.tessellation_deflection_mm.has_value());
  EXPECT_EQ(*scene.tessellation_deflection_mm, 0.05);
  SaveSceneYaml(scene, dir_ / "again.yaml");
  EXPECT_EQ(LoadScene(dir_ / "again.yaml").tessellation_deflection_mm, 0.05);
  for (const std::string bad : {"-1", ".nan", "\"0.1\"", "[1]"}) {
    try {
      LoadScene(write(bad));
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("tessellation_deflection must be a chord error in mm >= 0"),
                std::string::npos)
          << e.what();
    }
  }
}

// Two CAx-IF test models from other exporters (data/step/README.md).
// dm1's bolt overlaps its bore and its nut by the chord error (the
// polygons turned against each other) all along its shank: it comes out
// head first along the world's axis (its principal axis leans 4 mrad off
// it and drives the shank into the bore), the 87.8 mm pull proved in one
// swept query, and the exact check passes the written path. Before, each
// pose of the pull was a surface-depth search of 0.2 s and the bolt was
// NOT REMOVABLE at the time limit.
TEST_F(StepAssemblyTest, Dm1sBoltComesOutAlongItsBore) {
  const fs::path out = dir_ / "dm1";
  const auto scenes = testing::RunStageCommand(
      "assembly", "--assembly " + (testing::SourceDir() / "data" / "step" / "dm1-id-214-inch.step").string() + " -o " +
                      out.string() + " --dynamic bolt_3 2>&1");
  ASSERT_EQ(scenes.exit_code, 0) << scenes.output;
  const auto plan = testing::RunStageCommand("plan", "--scene " + (out / "bolt_3" / "scene.yaml").string() + " -o " +
                                                         (out / "bolt_3" / "path.h5").string() +
                                                         " --validity rigid-exact --time-limit 60 2>&1");
  EXPECT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("straight pull: D comes out along [0.0000, 1.0000, 0.0000]"), std::string::npos)
      << plan.output;
  EXPECT_NE(plan.output.find("exact check passed (2 poses, 1 stretches proved swept)"), std::string::npos)
      << plan.output;
}

TEST(PublicStepAssemblies, As1AndDm1ComeBackAsTheirTreesSay) {
  const fs::path data = testing::SourceDir() / "data" / "step";
  const StepAssembly as1 = ReadStepAssembly(data / "as1-oc-214.step", {});
  EXPECT_EQ(as1.file_units, "millimetre");
  ASSERT_EQ(as1.parts.size(), 18u);  // plate, rod, 2 rod nuts, 2 l-brackets, 6 bolts, 6 nuts
  EXPECT_EQ(as1.products, 5);        // plate, rod, nut, bolt, l-bracket
  std::map<std::string, int> by_product;
  for (const StepPart& part : as1.parts) {
    ++by_product[part.product];
    EXPECT_TRUE(IsClosedAndOriented(part.mesh)) << PathText(part);
    EXPECT_GT(Volume(part.mesh), 0) << PathText(part);
  }
  EXPECT_EQ(by_product,
            (std::map<std::string, int>{{"bolt", 6}, {"l-bracket", 2}, {"nut", 8}, {"plate", 1}, {"rod", 1}}));
  EXPECT_EQ(PathText(as1.parts[3]), "as1/l-bracket-assembly_1/nut-bolt-assembly_1/bolt_1");
  const Aabb plate = as1.parts[10].mesh.Bounds();
  EXPECT_NEAR(plate.max.x(), 180, 1e-6);
  EXPECT_NEAR(plate.max.y(), 150, 1e-6);

  // The same model from Pro/ENGINEER, in inch: each product holds its solid
  // and an empty compound, which XCAF makes components "SOLID" and
  // "COMPOUND"; the parts are named after their product, the compounds
  // have no triangles (left out of the scenes). Every length is 25.4 times
  // as1-oc's (the file has the mm model's numbers in inch).
  const StepAssembly pe = ReadStepAssembly(data / "as1-pe-203-inch.step", {});
  EXPECT_EQ(pe.file_units, "INCH");
  int solids = 0;
  for (const StepPart& part : pe.parts) solids += !part.mesh.triangles.empty();
  EXPECT_EQ(solids, 18);
  const std::vector<std::string> names = StepPartNames(pe, "x.obj");
  EXPECT_EQ(names[0], "PLATE");
  EXPECT_EQ(PathText(pe.parts[0]), "AS1_PE_ASM/PLATE/SOLID");
  const Aabb pe_plate = pe.parts[0].mesh.Bounds();
  EXPECT_NEAR((pe_plate.max - pe_plate.min).maxCoeff(), 180 * 25.4, 1e-6);

  const StepAssembly dm1 = ReadStepAssembly(data / "dm1-id-214-inch.step", {});
  EXPECT_EQ(dm1.file_units, "INCH");
  ASSERT_EQ(dm1.parts.size(), 7u);  // the material products have no shape
  const Aabb bracket = dm1.parts[0].mesh.Bounds();
  EXPECT_NEAR(bracket.max.z() - bracket.min.z(), 100, 1e-6);  // in mm

  // No face of these lies on another (a valid tessellation).
  for (const StepAssembly* assembly : {&as1, &pe, &dm1})
    for (const StepPart& part : assembly->parts) EXPECT_EQ(part.overlapping_surface_mm2, 0) << PathText(part);
}

// CATIA V5's s1 head back (data/step/README.md): a quarter of its outer
// sphere (radius 60 mm) comes back from OpenCASCADE as the other three
// quarters, over the neighbouring quarter and the front half. The mesh is
// not the part there, and that is said: about 20,800 mm^2 of its triangles
// lie on another face of the solid (the neighbouring quarter, about
// 10,800 mm^2, both ways).
TEST(PublicStepAssemblies, AFaceTessellatedBeyondItsBoundaryIsFound) {
  const StepAssembly head = ReadStepAssembly(testing::SourceDir() / "data" / "step" / "s1-c5-214-HEAD_BACK.step", {});
  ASSERT_EQ(head.parts.size(), 1u);
  const StepPart& part = head.parts[0];
  EXPECT_EQ(part.faces, 12);
  const Aabb box = part.mesh.Bounds();
  EXPECT_NEAR(box.max.x() - box.min.x(), 130, 0.1);  // 70 mm of the part, and 60 of the front half
  EXPECT_GT(part.overlapping_surface_mm2, 2 * 10000.0);
  EXPECT_LT(part.overlapping_surface_mm2, 2 * 11310.0);  // both ways over one quarter (4 pi 60^2 / 4 = 11,310)
}

TEST_F(StepAssemblyTest, BadInputIsAClearError) {
  const fs::path file = dir_ / "bench.step";
  testing::WriteStepFixture(file);
  std::ofstream(dir_ / "mesh.step") << "solid x\nendsolid x\n";
  const std::string full = testing::ReadTextFile(file);
  std::ofstream(dir_ / "cut.step") << full.substr(0, full.size() / 2);
  const struct {
    std::string arguments, message;
  } cases[] = {
      {"--assembly " + (dir_ / "none.step").string(), "none.step: file not found"},
      {"--assembly " + (dir_ / "mesh.step").string(), "mesh.step: not a STEP file"},
      {"--assembly " + (dir_ / "cut.step").string(), "cut.step: "},
      {"--assembly " + file.string() + " --deflection 0", "--deflection: must be a finite number > 0"},
      {"--assembly " + file.string() + " --deflection nan", "--deflection"},
      {"--assembly " + file.string() + " --angular-deflection 2", "--angular-deflection: must be at most 1.5"},
      {"--assembly " + file.string() + " --dynamic lid", "'lid' names no part of the assembly (parts: plate, pin"},
      {"--assembly " + file.string() + " --units none", "--units: a STEP assembly is tessellated in a length unit"},
  };
  for (const auto& c : cases) {
    const auto run = testing::RunStageCommand("assembly", c.arguments + " -o " + (dir_ / "o").string() + " 2>&1");
    EXPECT_EQ(run.exit_code, 2) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.message), std::string::npos) << c.arguments << "\n" << run.output;
  }
}

}  // namespace
}  // namespace ausbau
