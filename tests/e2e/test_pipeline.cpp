// End-to-end: the InIState pipeline (pipelines/inistate.mk) through make with
// the real executables on a small generated clip scene, and ausbau-verdict's
// input errors. One pipeline run is shared by the tests (the suite's
// set-up); a test that changes something works on its own copy of the scene
// and of that run's folder, so that the stages' caches see the same contents.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "inistate/tau_estimate.h"
#include "planning/path_io.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Outcome = testing::CommandOutcome;

// Runs a shell command, stdout and stderr together.
Outcome Shell(const std::string& command) {
  Outcome outcome;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return outcome;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) outcome.output += buffer;
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

// The pipeline on `scene` into `out`, with settings that keep it fast (one
// thread, coarse distance fields, fewer labeling load cases, no report).
// Most tests here exercise the volume pipeline (voxels, labels, tau, its
// caching), so they ask for VALIDITY=labeled-mliv; `validity` empty runs the
// pipeline's default (auto). Every run also checks that nothing outside OUT
// changed: the folder around it holds the test's scene (and the distance
// fields' cache no longer goes beside it).
Outcome RunPipeline(const fs::path& scene, const fs::path& out, const std::string& variables = "",
                    const std::string& validity = "labeled-mliv") {
  const std::string command =
      "make --no-print-directory -f " + (testing::SourceDir() / "pipelines/inistate.mk").string() +
      " BIN=" + testing::BinDir().string() + " SCENE=" + scene.string() + " OUT=" + out.string() +
      " THREADS=1 WITH_REPORT=0 TIME_LIMIT=30 DISTFIELD_FLAGS='--field-cells 64' "
      "LABEL_FLAGS='--max-load-cases 300' " +
      (validity.empty() ? "" : "VALIDITY=" + validity + " ") + variables;
  const testing::OutsideOut outside(out.parent_path(), out);
  const Outcome outcome = Shell(command);
  EXPECT_EQ(outside.Changes(), "") << "outside OUT " << out << " after:\n" << command;
  return outcome;
}

fs::file_time_type MTime(const fs::path& file) { return fs::last_write_time(file); }

bool UpToDate(const Outcome& outcome, const std::string& file) {
  return outcome.output.find(file + " is up to date") != std::string::npos;
}

// A member's line of verdict.json ("removable": true) - the file has one key
// per line.
bool HasLine(const std::string& json, const std::string& line) { return json.find(line) != std::string::npos; }

// The `exact_check` object's `valid` member (its first line).
bool ExactCheckValid(const std::string& json) {
  const auto at = json.find("\"exact_check\": {");
  return at != std::string::npos && json.find("\"valid\": true", at) == json.find("\"valid\": ", at);
}

class PipelineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto start = std::chrono::steady_clock::now();
    root_ = new fs::path(testing::MakeTempDir("pipeline"));
    const Outcome gen = testing::RunStageCommand(
        "scene-gen", "--family clips-ds1 --triangles 2000 --seed 1 -o " + (*root_ / "scene").string());
    ASSERT_EQ(gen.exit_code, 0) << gen.output;
    first_ = new Outcome(RunPipeline(*root_ / "scene/scene.yaml", *root_ / "out"));
    first_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    if (root_) fs::remove_all(*root_, ignored);
    delete root_;
    delete first_;
    root_ = nullptr;
    first_ = nullptr;
  }
  void SetUp() override { ASSERT_EQ(first_->exit_code, 0) << "the first pipeline run failed:\n" << first_->output; }

  // A copy of the scene and of the first run's folder under `name`.
  static fs::path Copy(const std::string& name) {
    const fs::path dir = *root_ / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy(*root_ / "scene", dir / "scene", fs::copy_options::recursive);
    fs::copy(*root_ / "out", dir / "out", fs::copy_options::recursive);
    return dir;
  }
  static fs::path Out() { return *root_ / "out"; }

  static fs::path* root_;
  static Outcome* first_;
  static double first_seconds_;
};
fs::path* PipelineTest::root_ = nullptr;
Outcome* PipelineTest::first_ = nullptr;
double PipelineTest::first_seconds_ = 0;

TEST_F(PipelineTest, WritesTheSmoothedPathAsPathCsvAndARemovableVerdict) {
  std::printf("first pipeline run: %.1f s\n", first_seconds_);
  for (const char* name :
       {"voxels.h5", "spheres.h5", "labels.h5", "distfield-static.h5", "distfield-dynamic.h5", "tau.h5",
        "tau-trace.csv", "path.h5", "path-smooth.h5", "path-smooth.csv", "profile.csv", "path.csv", "verdict.json"}) {
    EXPECT_TRUE(fs::exists(Out() / name)) << name;
  }
  const std::string csv = testing::ReadTextFile(Out() / "path.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "x,y,z,qw,qx,qy,qz");
  EXPECT_EQ(csv, testing::ReadTextFile(Out() / "path-smooth.csv")) << "path.csv must be the smoothed path";
  const PathArtifact smoothed = ReadPathArtifact(Out() / "path-smooth.h5");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), smoothed.waypoints.size() + 1);

  const std::string json = testing::ReadTextFile(Out() / "verdict.json");
  EXPECT_TRUE(HasLine(json, "\"schema\": \"ausbau-verdict\"")) << json;
  EXPECT_TRUE(HasLine(json, "\"version\": 1")) << json;
  EXPECT_TRUE(HasLine(json, "\"removable\": true")) << json;
  EXPECT_TRUE(HasLine(json, "\"status\": \"removable\"")) << json;
  EXPECT_TRUE(HasLine(json, "\"validity\": \"labeled-mliv\"")) << json;
  EXPECT_TRUE(HasLine(json, "\"max_labeled_mliv\": {")) << json;
  EXPECT_TRUE(HasLine(json, "\"csv\": \"" + (Out() / "path.csv").string() + "\"")) << json;
  EXPECT_TRUE(HasLine(json, "\"waypoints\": " + std::to_string(smoothed.waypoints.size()))) << json;
  for (const char* stage :
       {"voxelize", "medial-spheres", "pbd-label", "distfield-build", "tau-estimate", "plan", "smooth"}) {
    EXPECT_TRUE(HasLine(json, std::string("\"") + stage + "\": ")) << stage << " missing in " << json;
  }
  EXPECT_NE(first_->output.find("REMOVABLE"), std::string::npos) << first_->output;
  // The path's quality figures and clearance (the default, 0.5 mm here:
  // the scene is in mm), and profile.csv's units and poses.
  EXPECT_TRUE(HasLine(json, "\"path_quality\": {")) << json;
  EXPECT_TRUE(HasLine(json, "\"clearance_kept\": 0.5,")) << json;
  EXPECT_TRUE(HasLine(json, "\"segment_clearance\": [")) << json;
  const std::string profile = testing::ReadTextFile(Out() / "profile.csv");
  EXPECT_EQ(profile.rfind("# units: tx,ty,tz,clearance in mm;", 0), 0u) << profile.substr(0, 200);
  EXPECT_NE(profile.find("\nsegment,fraction,s,tx,ty,tz,qw,qx,qy,qz,volume,part,deformability,clearance\n"),
            std::string::npos);
  // plan takes the sigma_1 that tau-estimate's last round found (same tau,
  // psi, planner, seed) instead of planning it again.
  EXPECT_TRUE(ReadTauArtifact(Out() / "tau.h5").estimate.solved);
  EXPECT_NE(first_->output.find("part 1 (known path, re-checked"), std::string::npos) << first_->output;
}

TEST_F(PipelineTest, ANewSeedReRunsOnlyThePlanningStages) {
  const fs::path dir = Copy("seed");
  std::map<std::string, fs::file_time_type> before;
  for (const char* name : {"voxels.h5", "spheres.h5", "labels.h5", "distfield-static.h5", "distfield-dynamic.h5"}) {
    before[name] = MTime(dir / "out" / name);
  }
  const Outcome again = RunPipeline(dir / "scene/scene.yaml", dir / "out", "SEED=2 TIME_LIMIT=29");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  for (const auto& [name, time] : before) {
    EXPECT_TRUE(UpToDate(again, (dir / "out" / name).string())) << name << " was redone:\n" << again.output;
    EXPECT_EQ(MTime(dir / "out" / name), time) << name << " was rewritten";
  }
  for (const char* name : {"tau.h5", "path.h5", "path-smooth.h5"}) {
    EXPECT_FALSE(UpToDate(again, (dir / "out" / name).string())) << name << " was not redone:\n" << again.output;
  }
  EXPECT_TRUE(HasLine(testing::ReadTextFile(dir / "out/verdict.json"), "\"removable\": true"));
  // And a run with nothing changed redoes nothing.
  const Outcome same = RunPipeline(dir / "scene/scene.yaml", dir / "out", "SEED=2 TIME_LIMIT=29");
  ASSERT_EQ(same.exit_code, 0) << same.output;
  for (const char* name : {"voxels.h5", "labels.h5", "tau.h5", "path.h5", "path-smooth.h5"}) {
    EXPECT_TRUE(UpToDate(same, (dir / "out" / name).string())) << name << ":\n" << same.output;
  }
}

// The thesis's alg. 12 without the fastener guard is a validity mode of its
// own: switching to it re-runs tau and planning on the cached voxels and labels.
TEST_F(PipelineTest, TheUnguardedModeReusesVoxelsAndLabels) {
  const fs::path dir = Copy("unguarded");
  const Outcome run = RunPipeline(dir / "scene/scene.yaml", dir / "out", "VALIDITY=labeled-mliv-unguarded");
  // Alg. 12 alone lets a rigid part graze S by up to tau / colorValue (less
  // than a voxel here): its path may fail the verdict's exact check (exit 3,
  // not removable; make then fails). Either way the run reached its verdict.
  ASSERT_TRUE(run.exit_code == 0 || run.output.find("FAILED: a rigid part of D penetrates S") != std::string::npos)
      << run.output;
  ASSERT_TRUE(fs::exists(dir / "out/verdict.json")) << run.output;
  for (const char* name : {"voxels.h5", "labels.h5"}) {
    EXPECT_TRUE(UpToDate(run, (dir / "out" / name).string())) << name << " was redone:\n" << run.output;
  }
  for (const char* name : {"tau.h5", "path.h5"}) {
    EXPECT_FALSE(UpToDate(run, (dir / "out" / name).string())) << name << " was not redone:\n" << run.output;
  }
  EXPECT_EQ(ReadTauArtifact(dir / "out/tau.h5").validity, ValidityMode::kLabeledMlivUnguarded);
  EXPECT_TRUE(HasLine(testing::ReadTextFile(dir / "out/verdict.json"), "\"validity\": \"labeled-mliv-unguarded\""));
  // The guarded run said what its guard allows; the unguarded one has none.
  EXPECT_NE(first_->output.find("fastener guard:"), std::string::npos) << first_->output;
  EXPECT_EQ(run.output.find("fastener guard:"), std::string::npos) << run.output;
}

TEST_F(PipelineTest, ChangingDsMeshReRunsEverythingThatDependsOnD) {
  const fs::path dir = Copy("mesh");
  // Move one vertex of D by a hair (0.1% of a millimetre).
  const fs::path obj = dir / "scene/part.obj";
  std::istringstream in(testing::ReadTextFile(obj));
  std::ostringstream edited;
  std::string line;
  bool done = false;
  while (std::getline(in, line)) {
    if (!done && line.rfind("v ", 0) == 0) {
      double x, y, z;
      ASSERT_EQ(std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z), 3) << line;
      char buffer[128];
      std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g", x + 1e-3, y, z);
      line = buffer;
      done = true;
    }
    edited << line << "\n";
  }
  std::ofstream(obj) << edited.str();
  const Outcome again = RunPipeline(dir / "scene/scene.yaml", dir / "out");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  for (const char* name :
       {"voxels.h5", "spheres.h5", "labels.h5", "distfield-dynamic.h5", "tau.h5", "path.h5", "path-smooth.h5"}) {
    EXPECT_FALSE(UpToDate(again, (dir / "out" / name).string())) << name << " was not redone:\n" << again.output;
  }
  // S did not change: its distance field is reused.
  EXPECT_TRUE(UpToDate(again, (dir / "out/distfield-static.h5").string())) << again.output;
}

TEST_F(PipelineTest, AStageCanBeSwappedByItsVariable) {
  const fs::path dir = Copy("swap");
  const fs::path wrapper = dir / "my-verdict.sh";
  // (The mark goes into OUT: RunPipeline checks that nothing outside changed.)
  std::ofstream(wrapper) << "#!/bin/sh\necho swapped > \"" << (dir / "out/swapped").string() << "\"\nexec "
                         << (testing::BinDir() / "ausbau-verdict").string() << " \"$@\"\n";
  fs::permissions(wrapper, fs::perms::owner_all, fs::perm_options::add);
  const Outcome run = RunPipeline(dir / "scene/scene.yaml", dir / "out", "VERDICT=" + wrapper.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(fs::exists(dir / "out/swapped")) << run.output;
  EXPECT_TRUE(HasLine(testing::ReadTextFile(dir / "out/verdict.json"), "\"removable\": true"));
}

TEST_F(PipelineTest, NoPathStillWritesAVerdictAndMakeFails) {
  const fs::path dir = Copy("nopath");
  const Outcome run = RunPipeline(dir / "scene/scene.yaml", dir / "out", "PLAN_FLAGS='--max-iterations 1'");
  EXPECT_NE(run.exit_code, 0) << run.output;
  const std::string json = testing::ReadTextFile(dir / "out/verdict.json");
  EXPECT_TRUE(HasLine(json, "\"removable\": false")) << json << run.output;
  EXPECT_TRUE(HasLine(json, "\"status\": \"not-removable\"")) << json;
  EXPECT_FALSE(fs::exists(dir / "out/path.csv")) << "a stale path.csv survived";
  EXPECT_FALSE(fs::exists(dir / "out/path-smooth.h5"));
  EXPECT_NE(run.output.find("not removable"), std::string::npos) << run.output;
}

TEST_F(PipelineTest, TheDefaultPicksTheExactRigidCheckWhereItCanMeasure) {
  // A box-soup panel metres from the origin: clips, a rail under a lip, a pin.
  const fs::path scene = *root_ / "panel";
  const Outcome gen = testing::RunStageCommand("scene-gen", "--family panel-tilt-slide --seed 1 -o " + scene.string());
  ASSERT_EQ(gen.exit_code, 0) << gen.output;
  const fs::path dir = *root_ / "exact";
  // VALIDITY=auto given on the command line (the default, as a user types
  // it): resolved as when it is not given.
  const Outcome run = RunPipeline(scene / "scene.yaml", dir, "", "auto");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* name : {"voxels.h5", "spheres.h5", "labels.h5", "tau.h5", "distfield-static.h5"}) {
    EXPECT_FALSE(fs::exists(dir / name)) << name;
  }
  const std::string json = testing::ReadTextFile(dir / "verdict.json");
  EXPECT_TRUE(HasLine(json, "\"removable\": true")) << json;
  EXPECT_TRUE(HasLine(json, "\"validity\": \"rigid-exact\"")) << json;
  EXPECT_TRUE(ExactCheckValid(json)) << json;

  EXPECT_NE(run.output.find("VALIDITY=auto: rigid-exact"), std::string::npos) << run.output;

  // The clip scene's plate is one welded, non-convex mesh: the clips' depth
  // in it is measured on the surfaces (collision/mesh_depth.h), so
  // rigid-exact frees them as fasteners and the path passes the exact check;
  // the default (auto) still hands clips in a non-convex S to the volume
  // model, which bounds how far each clip bends.
  const Outcome measured = RunPipeline(*root_ / "scene/scene.yaml", *root_ / "exact-ds1", "", "rigid-exact");
  EXPECT_EQ(measured.exit_code, 0) << measured.output;
  const std::string ds1 = testing::ReadTextFile(*root_ / "exact-ds1/verdict.json");
  EXPECT_TRUE(HasLine(ds1, "\"removable\": true")) << ds1;
  EXPECT_TRUE(ExactCheckValid(ds1)) << ds1;
  EXPECT_EQ(measured.output.find("depth is not measured"), std::string::npos) << measured.output;
  const Outcome chosen = Shell((testing::BinDir() / "ausbau-plan").string() + " --scene " +
                               (*root_ / "scene/scene.yaml").string() + " --choose-validity --log-level error");
  EXPECT_EQ(chosen.exit_code, 0) << chosen.output;
  EXPECT_EQ(chosen.output, "labeled-mliv\n");
}

TEST_F(PipelineTest, TheVerdictChecksThePathCsvAsWritten) {
  // A path.csv that pushes the panel 20 mm down through the plate before
  // leaving: the planner's own artifact is fine, the file is not.
  const fs::path dir = Copy("doctored");
  std::ofstream(dir / "doctored.csv") << "# edited by hand\nx,y,z,qw,qx,qy,qz\n0,0,0,1,0,0,0\n0,0,-20,1,0,0,0\n"
                                      << "0,0,-20,1,0,0,0\n0,0,500,1,0,0,0\n";
  const Outcome run = testing::RunStageCommand(
      "verdict", "--scene " + (dir / "scene/scene.yaml").string() + " --path " + (dir / "out/path-smooth.h5").string() +
                     " --csv-name " + (dir / "doctored.csv").string() + " -o " + (dir / "verdict.json").string());
  EXPECT_EQ(run.exit_code, 3) << run.output;
  const std::string json = testing::ReadTextFile(dir / "verdict.json");
  EXPECT_TRUE(HasLine(json, "\"removable\": false")) << json;
  EXPECT_TRUE(HasLine(json, "\"exact_check\": {")) << json;
  EXPECT_FALSE(ExactCheckValid(json)) << json;
  EXPECT_NE(json.find("penetrates S"), std::string::npos) << json;
  // Not removable: what holds D, from straight pulls (README "What the
  // verdict promises").
  EXPECT_NE(json.find("\"what_blocks\": {"), std::string::npos) << json;
  EXPECT_NE(json.find("\"straight_pulls\": ["), std::string::npos) << json;
  EXPECT_NE(run.output.find("what blocks: "), std::string::npos) << run.output;
}

// ---- the end-to-end benchmark (ausbau-inistate-bench --end-to-end)

TEST(EndToEndBench, RunsThePipelineAndJudgesEachPathWithTheOracle) {
  const fs::path external = testing::SourceDir() / "../shared/benchmarks/inistate-external";
  if (!fs::exists(external / "oracle.py")) GTEST_SKIP() << "no " << external / "oracle.py";
  if (Shell("/usr/bin/python3 -c 'import numpy'").exit_code != 0) GTEST_SKIP() << "python3 without numpy";
  const fs::path out = testing::MakeTempDir("end-to-end");
  const Outcome run =
      Shell((testing::BinDir() / "ausbau-inistate-bench").string() +
            " --end-to-end --families panel-straight-pull --seeds 1 --skip-external-scenes --external " +
            external.string() + " --pipeline " + (testing::SourceDir() / "pipelines/inistate.mk").string() + " --bin " +
            testing::BinDir().string() + " --output-dir " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string summary = testing::ReadTextFile(out / "end-to-end-summary.md");
  EXPECT_NE(summary.find("| panel-straight-pull-coarse | 1 | 1 | 0 | 0 |"), std::string::npos) << summary;
  EXPECT_NE(summary.find("| panel-straight-pull-fine | 1 | 1 | 0 | 0 |"), std::string::npos) << summary;
  // The moulded twin (D one welded solid) comes out the same way.
  EXPECT_NE(summary.find("| panel-straight-pull-molded | 1 | 1 | 0 | 0 |"), std::string::npos) << summary;
  const std::string csv = testing::ReadTextFile(out / "end-to-end-results.csv");
  EXPECT_EQ(csv.rfind("family,scene,verdict,checker,result,rigid_penetration,seconds\n", 0), 0u) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4) << csv;
  // A bad family is one line and exit 2, before any work.
  const Outcome bad = Shell((testing::BinDir() / "ausbau-inistate-bench").string() +
                            " --end-to-end --families panel-nothing --output-dir " + out.string() + " --pipeline " +
                            (testing::SourceDir() / "pipelines/inistate.mk").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("unknown family 'panel-nothing'"), std::string::npos) << bad.output;
}

// ---- ausbau-verdict on its own

void ExpectOneLineError(const Outcome& outcome, const std::string& fragment) {
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  const std::string prefix = "ausbau-verdict: error: ";
  const auto at = outcome.output.find(prefix);
  ASSERT_NE(at, std::string::npos) << outcome.output;
  const std::string line = outcome.output.substr(at);
  EXPECT_EQ(line.find('\n'), line.size() - 1) << "more than one line: " << line;
  EXPECT_NE(line.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << line;
}

TEST_F(PipelineTest, VerdictExitCodesAndBadInputs) {
  const std::string scene = "--scene " + (*root_ / "scene/scene.yaml").string();
  const fs::path out = testing::MakeTempDir("verdict");
  const std::string o = " -o " + (out / "v.json").string();
  // Removable: 0; a path artifact without a path: 3.
  const Outcome ok =
      testing::RunStageCommand("verdict", scene + " --path " + (Out() / "path-smooth.h5").string() + " --tau-file " +
                                              (Out() / "tau.h5").string() + " --budget 1e6" + o);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  const std::string json = testing::ReadTextFile(out / "v.json");
  EXPECT_TRUE(HasLine(json, "\"within_budget\": true")) << json;
  EXPECT_TRUE(HasLine(json, "\"csv\": null")) << json;

  ExpectOneLineError(testing::RunStageCommand("verdict", scene + " --path " + (out / "missing.h5").string() + o),
                     "missing.h5");
  ExpectOneLineError(testing::RunStageCommand("verdict", scene + " --path " + (Out() / "labels.h5").string() + o),
                     "schema");
  ExpectOneLineError(testing::RunStageCommand("verdict", scene + " --path " + (Out() / "path.h5").string() +
                                                             " --tau-file " + (Out() / "path.h5").string() + o),
                     "schema");
  std::ofstream(out / "not-hdf5.h5") << "not an artifact\n";
  ExpectOneLineError(testing::RunStageCommand("verdict", scene + " --path " + (out / "not-hdf5.h5").string() + o),
                     "not-hdf5.h5");
  fs::create_directories(out / "times");
  std::ofstream(out / "times/plan.seconds") << "fast\n";
  ExpectOneLineError(testing::RunStageCommand("verdict", scene + " --path " + (Out() / "path.h5").string() +
                                                             " --times " + (out / "times").string() + o),
                     "plan.seconds");
  EXPECT_EQ(testing::RunStageCommand("verdict", scene + " --path " + (Out() / "path.h5").string() + " --budget -1" + o)
                .exit_code,
            2);
}

// Names reach the recipes' shell: a scene folder named like a command, or
// an OUT with a space, stops the run before any recipe (exit 2, naming it),
// and nothing runs or is written.
TEST(PipelineNames, ShellCodeInANameStopsTheRunBeforeAnyRecipe) {
  const fs::path dir = testing::MakeTempDir("names");
  const auto scene_folder = [&](const std::string& name) {
    fs::create_directories(dir / "scenes" / name);
    std::ofstream(dir / "scenes" / name / "scene.yaml") << "format: ausbau-scene/1\n";
  };
  scene_folder("x$(touch${IFS}PWNED)");
  scene_folder("a,$(touch${IFS}COMMA)");  // a comma would split make's function arguments around the check
  scene_folder("good");
  const testing::OutsideOut outside(dir, dir / "out");
  // make -f pipelines/<makefile> in `dir`, every name single-quoted.
  const auto make = [&](const std::string& makefile, const std::string& variables) {
    return Shell("make --no-print-directory -C '" + dir.string() + "' -f '" +
                 (testing::SourceDir() / "pipelines" / makefile).string() + "' " + variables + " BIN='" +
                 testing::BinDir().string() + "'");
  };
  const Outcome outcome = make("batch.mk", "SCENES=scenes OUT=out");
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  EXPECT_NE(outcome.output.find("would reach a shell"), std::string::npos) << outcome.output;
  EXPECT_FALSE(fs::exists(dir / "PWNED"));
  EXPECT_FALSE(fs::exists(dir / "COMMA"));
  EXPECT_FALSE(fs::exists(dir / "out"));

  const Outcome spaced = make("inistate.mk", "SCENE=scenes/good/scene.yaml 'OUT=o ut'");
  EXPECT_EQ(spaced.exit_code, 2) << spaced.output;
  EXPECT_NE(spaced.output.find("OUT=o ut"), std::string::npos) << spaced.output;
  EXPECT_FALSE(fs::exists(dir / "o"));
  EXPECT_FALSE(fs::exists(dir / "o ut"));
  EXPECT_EQ(outside.Changes(), "");
}

}  // namespace
}  // namespace ausbau
