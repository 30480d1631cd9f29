// End-to-end: the real executables on generated scenes. Exit codes, one-line
// messages, outputs, caching and determinism.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "artifact/artifact.h"
#include "core/error.h"
#include "core/hash.h"
#include "fixtures/box_scenes.h"
#include "fixtures/scene_families.h"
#include "generated_scene.h"
#include "geometry/primitives.h"
#include "inistate/tau_estimate.h"
#include "inistate/voxel_grid.h"
#include "planning/dense_check.h"
#include "planning/exact_check.h"
#include "planning/path_io.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

using Outcome = testing::CommandOutcome;

Outcome RunStage(const std::string& stage, const std::string& arguments) {
  return testing::RunStageCommand(stage, arguments);
}

std::string ReadFile(const std::filesystem::path& path) { return testing::ReadTextFile(path); }

void WriteFile(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

// The error line: "ausbau-<stage>: error: ..." and nothing after it.
void ExpectOneLineError(const Outcome& outcome, const std::string& stage, const std::string& fragment) {
  const std::string prefix = "ausbau-" + stage + ": error: ";
  const auto at = outcome.output.find(prefix);
  ASSERT_NE(at, std::string::npos) << outcome.output;
  const std::string line = outcome.output.substr(at);
  EXPECT_EQ(line.find('\n'), line.size() - 1) << "more than one line: " << line;
  EXPECT_NE(line.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << line;
}

TEST(PlanStage, PlansSmoothsAndTheResultIsValid) {
  const auto yaml = testing::MakeGeneratedScene("rod-in-cage", 2);
  const auto dir = yaml.parent_path();
  const Outcome plan = RunStage("plan", "--scene " + yaml.string() + " --seed 4 -o " + (dir / "path.h5").string() +
                                            " --csv " + (dir / "path.csv").string());
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  const Outcome smooth =
      RunStage("smooth", "--scene " + yaml.string() + " --path " + (dir / "path.h5").string() + " -o " +
                             (dir / "smooth.h5").string() + " --csv " + (dir / "smooth.csv").string());
  ASSERT_EQ(smooth.exit_code, 0) << smooth.output;
  EXPECT_NE(smooth.output.find("length"), std::string::npos);

  const Scene scene = LoadScene(yaml);
  for (const char* name : {"path.h5", "smooth.h5"}) {
    const PathArtifact path = ReadPathArtifact(dir / name);
    EXPECT_TRUE(path.success);
    ASSERT_GE(path.waypoints.size(), 2u);
    EXPECT_TRUE(path.waypoints.front().t.isApprox(scene.start.t));
    const DenseCheckReport report = DenseCheckPath(scene, path.reference_point, path.waypoints, 0.0025);
    EXPECT_TRUE(report.valid) << name << ": segment " << report.first_bad_segment << " " << report.reason;
  }
  EXPECT_LE(ReadPathArtifact(dir / "smooth.h5").length_normalized, ReadPathArtifact(dir / "path.h5").length_normalized);
  const std::string csv = ReadFile(dir / "path.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "x,y,z,qw,qx,qy,qz");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), ReadPathArtifact(dir / "path.h5").waypoints.size() + 1);
}

// Under plain collision, on a part placed metres from its mesh origin (the
// L-channel family): both CSVs, read back as any tool reads them (rows
// interpolated about the mesh origin), pass the exact check. The planner and
// the smoother move D about its reference point; the rows they write must be
// close enough for the plain reading (README "What the verdict promises").
// Without the split in ausbau-plan, path.csv fails here (4.7 mm); the
// smoother's own split guards shortcuts that turn D (on this scene its
// rows hold either way).
TEST(SmoothStage, CollisionPathsHoldUnderPlainInterpolation) {
  // Scene seed 4 with plan seed 1 once stopped with an internal error: the
  // dense re-check found a pose of the certified path 0.2 mm from the walls
  // in S; the path is now certified again at a finer step (plan_scene.cpp).
  // (scene seed, plan seed)
  for (const auto& [scene_seed, plan_seed] : {std::pair<std::uint64_t, int>{1, 2}, {4, 1}}) {
    BoxSceneOptions options;
    options.seed = scene_seed;
    options.world = BoxWorld::kRandom;
    const auto dir = testing::MakeTempDir("panel-channel-" + std::to_string(scene_seed));
    const auto yaml = GenerateBoxScene("panel-channel", options, dir / "scene").scene_yaml;
    const Outcome plan = RunStage("plan", "--scene " + yaml.string() + " --seed " + std::to_string(plan_seed) +
                                              " --validity collision -o " + (dir / "path.h5").string() + " --csv " +
                                              (dir / "path.csv").string());
    ASSERT_EQ(plan.exit_code, 0) << plan.output;
    const Outcome smooth =
        RunStage("smooth", "--scene " + yaml.string() + " --path " + (dir / "path.h5").string() + " -o " +
                               (dir / "smooth.h5").string() + " --csv " + (dir / "smooth.csv").string());
    ASSERT_EQ(smooth.exit_code, 0) << smooth.output;
    // Smoothing step 5's gate, both ways: with scene seed 1 (plan seed 2)
    // the smoothed path still turns D by more than 0.1 rad in all and the
    // translation-only alternative is planned; with scene seed 4 it turns
    // less, and it is not. (Plan seed 1 on scene seed 1 turned more than 0.1 rad
    // until the planner's tree grew from where the straight pulls stop
    // too; now it turns 0.03 rad.)
    // Seed 4's smoothed path once failed the dense re-check (a shortcut
    // grazing S between two checked poses) and the input path, turning
    // 2.07 rad, was written; it is smoothed again at a finer step now.
    const std::string tried = "translation-only alternative: tried (the path turns D ";
    const std::string skipped = "translation-only alternative: not tried (the path turns D ";
    const auto at_tried = smooth.output.find(tried), at_skipped = smooth.output.rfind(skipped);
    if (scene_seed == 1) {
      ASSERT_NE(at_tried, std::string::npos) << smooth.output;
      EXPECT_GT(std::stod(smooth.output.substr(at_tried + tried.size())), 0.1);
    } else {
      ASSERT_NE(at_skipped, std::string::npos) << smooth.output;
      EXPECT_LE(std::stod(smooth.output.substr(at_skipped + skipped.size())), 0.1);
      EXPECT_LE(ReadPathArtifact(dir / "smooth.h5").length_rotation, 0.1) << smooth.output;
    }
    const Scene scene = LoadScene(yaml);
    for (const char* name : {"path.csv", "smooth.csv"}) {
      const ExactCheckReport check = ExactCheckPath(scene, ReadPathCsv(dir / name), 0.05);
      EXPECT_TRUE(check.valid) << "scene seed " << scene_seed << ", " << name << ": " << check.reason;
      EXPECT_LE(check.max_rigid_depth, 0.05) << "scene seed " << scene_seed << ", " << name;
    }
  }
}

// The translation-only alternative (docs/planning.md, smoothing step 5) is
// planned only where the smoothed path still turns D by more than 0.1 rad
// in all. On the demo panel (clips, a rail under a lip: no way out without
// a tilt) the turning left is a few hundredths of a radian, and the
// alternative's 20,000 iterations, which never got out, were most of the
// smoothing's time.
TEST(SmoothStage, NoTranslationOnlyAlternativeWhereThePathBarelyTurns) {
  const auto yaml = testing::SourceDir() / "scenes/panel-tilt-slide-1/scene.yaml";
  const auto dir = testing::MakeTempDir("demo-alternative");
  const Outcome plan =
      RunStage("plan", "--scene " + yaml.string() + " --validity rigid-exact -o " + (dir / "path.h5").string());
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  const Outcome smooth = RunStage("smooth", "--scene " + yaml.string() + " --path " + (dir / "path.h5").string() +
                                                " -o " + (dir / "smooth.h5").string());
  ASSERT_EQ(smooth.exit_code, 0) << smooth.output;
  EXPECT_EQ(smooth.output.find("translation-only alternative: tried"), std::string::npos) << smooth.output;
  const std::string marker = "translation-only alternative: not tried (the path turns D ";
  const auto at = smooth.output.find(marker);
  ASSERT_NE(at, std::string::npos) << smooth.output;
  const double turn = std::stod(smooth.output.substr(at + marker.size()));
  EXPECT_GT(turn, 0.0);
  EXPECT_LE(turn, 0.1);
  const PathArtifact smoothed = ReadPathArtifact(dir / "smooth.h5");
  EXPECT_TRUE(smoothed.success);
  EXPECT_TRUE(ExactCheckPath(LoadScene(yaml), smoothed.waypoints, 0.05).valid);
}

// A key in a keyhole slot (panel-keyhole seed 4, D about 60 mm across):
// planned without exit moves with seed 2, its certified path grazed a wall
// of S 0.057 mm deep between two poses (the certification's step, 0.15 mm,
// is wider than twice the rigid tolerance), which the exact check caught,
// and the run ended with no path. The path is now certified again at a
// finer step, like one the dense re-check finds in S. (With single pulls
// only: that path's tree grew from the start alone, before the planner's
// tree also grew from where the straight pulls stop; plan seeds 1-29 with
// the default two legs gave no path the exact check rejects.)
TEST(PlanStage, APathTheExactCheckRejectsIsCertifiedAgain) {
  BoxSceneOptions options;
  options.seed = 4;
  options.world = BoxWorld::kRandom;
  const auto dir = testing::MakeTempDir("panel-keyhole-4");
  const auto yaml = GenerateBoxScene("panel-keyhole", options, dir / "scene").scene_yaml;
  const Outcome plan = RunStage("plan", "--scene " + yaml.string() + " --seed 2 --exit-axes 0 --pull-legs 1 -o " +
                                            (dir / "path.h5").string() + " --csv " + (dir / "path.csv").string());
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("the exact check finds"), std::string::npos) << plan.output;
  const ExactCheckReport check = ExactCheckPath(LoadScene(yaml), ReadPathCsv(dir / "path.csv"), 0.05);
  EXPECT_TRUE(check.valid) << check.reason;
}

TEST(PlanStage, SameSeedGivesAByteIdenticalCsv) {
  const auto yaml = testing::MakeGeneratedScene("rod-in-cage", 3);
  const auto dir = yaml.parent_path();
  for (const char* name : {"a", "b"}) {
    const Outcome plan =
        RunStage("plan", "--scene " + yaml.string() + " --seed 7 -o " + (dir / (std::string(name) + ".h5")).string() +
                             " --csv " + (dir / (std::string(name) + ".csv")).string());
    ASSERT_EQ(plan.exit_code, 0) << plan.output;
  }
  EXPECT_EQ(ReadFile(dir / "a.csv"), ReadFile(dir / "b.csv"));
  EXPECT_EQ(ReadFile(dir / "a.h5").size(), ReadFile(dir / "b.h5").size());
}

TEST(PlanStage, WritesOmplsPathFormat) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  const auto dir = yaml.parent_path();
  const Outcome plan =
      RunStage("plan", "--scene " + yaml.string() + " --planner prm --threads 2 -o " + (dir / "p.h5").string() +
                           " --csv " + (dir / "p.csv").string() + " --ompl-path " + (dir / "p.path").string());
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  // Same poses, OMPL's order: x y z qx qy qz qw.
  std::istringstream csv(ReadFile(dir / "p.csv")), ompl(ReadFile(dir / "p.path"));
  std::string header, row, line;
  std::getline(csv, header);
  int rows = 0;
  while (std::getline(csv, row) && std::getline(ompl, line)) {
    double c[7], o[7];
    ASSERT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &c[0], &c[1], &c[2], &c[3], &c[4], &c[5], &c[6]),
              7);
    std::istringstream fields(line);
    for (double& v : o) fields >> v;
    ASSERT_TRUE(fields) << line;
    EXPECT_EQ(c[0], o[0]);
    EXPECT_EQ(c[2], o[2]);
    EXPECT_EQ(c[3], o[6]);  // qw last in OMPL's format
    EXPECT_EQ(c[4], o[3]);
    ++rows;
  }
  EXPECT_GE(rows, 2);
  EXPECT_FALSE(std::getline(ompl, line));
}

TEST(PlanStage, ReusesAnUpToDateOutputAndReplansOnChange) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  const auto out = (yaml.parent_path() / "path.h5").string();
  const std::string base = "--scene " + yaml.string() + " -o " + out;
  ASSERT_EQ(RunStage("plan", base).exit_code, 0);
  const Outcome again = RunStage("plan", base);
  EXPECT_EQ(again.exit_code, 0);
  EXPECT_NE(again.output.find("up to date"), std::string::npos) << again.output;
  const Outcome other_seed = RunStage("plan", base + " --seed 2");
  EXPECT_EQ(other_seed.output.find("up to date"), std::string::npos) << other_seed.output;
  const Outcome forced = RunStage("plan", base + " --seed 2 --force");
  EXPECT_EQ(forced.output.find("up to date"), std::string::npos) << forced.output;
}

// The runner (cli/stage.h) says "up to date" once, in the stage's words
// (StageSpec::up_to_date), then runs the stage's reuse step (here: the CSV
// written again); a Query flag (--choose-validity) answers without the cache.
TEST(StageRunner, UpToDateLineReuseAndQuery) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  const auto dir = yaml.parent_path();
  const std::string base = "--scene " + yaml.string() + " -o " + (dir / "path.h5").string();
  ASSERT_EQ(RunStage("plan", base).exit_code, 0);
  const Outcome again = RunStage("plan", base + " --csv " + (dir / "again.csv").string());
  EXPECT_EQ(again.exit_code, 0) << again.output;
  const std::string line =
      (dir / "path.h5").string() + " is up to date (same inputs and options); use --force to plan again";
  const auto at = again.output.find(line);
  ASSERT_NE(at, std::string::npos) << again.output;
  EXPECT_EQ(again.output.find("up to date", at + line.size()), std::string::npos) << "said twice: " << again.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "again.csv")) << "the reuse step did not write the CSV";

  const Outcome query = RunStage("plan", base + " --choose-validity");
  EXPECT_EQ(query.exit_code, 0) << query.output;
  EXPECT_EQ(query.output.find("up to date"), std::string::npos) << query.output;
  EXPECT_NE(query.output.find("rigid-exact"), std::string::npos) << query.output;

  const std::string spheres = "--scene " + yaml.string() + " -o " + (dir / "spheres.h5").string();
  ASSERT_EQ(RunStage("medial-spheres", spheres).exit_code, 0);
  const Outcome reused = RunStage("medial-spheres", spheres);
  EXPECT_EQ(reused.exit_code, 0) << reused.output;
  EXPECT_NE(reused.output.find("is up to date (same D and options); use --force to compute again"), std::string::npos)
      << reused.output;
}

TEST(PlanStage, NoPathWithinTheBudgetHasItsOwnExitCode) {
  // The rod in a cage whose lid has no slot: no way out.
  const auto yaml = testing::MakeGeneratedScene("rod-in-cage", 1);
  const auto dir = yaml.parent_path();
  std::string text = ReadFile(yaml);
  const Scene scene = LoadScene(yaml);
  TriangleMesh closed = scene.static_mesh;
  const Aabb box = closed.Bounds();
  closed.Append(MakeBox({box.min.x(), box.min.y(), box.max.z() - 1.0}, box.max));  // a solid lid
  SaveObj(closed, dir / "environment.obj");
  const Outcome plan = RunStage("plan", "--scene " + yaml.string() + " --time-limit 1 -o " + (dir / "p.h5").string() +
                                            " --csv " + (dir / "p.csv").string());
  EXPECT_EQ(plan.exit_code, 3) << plan.output;
  ExpectOneLineError(plan, "plan", "no path within the budget");
  EXPECT_FALSE(std::filesystem::exists(dir / "p.csv"));
  EXPECT_FALSE(ReadPathArtifact(dir / "p.h5").success);
}

// An interrupted stage (SIGINT, as Ctrl-C; `timeout` sends it here) stops
// at its next safe point, says so, exits 130 and leaves the output that was
// there before untouched: a planner stopped early is no "not removable".
// `--foreground`: without it GNU timeout signals the stage and then its own
// process group, which holds the stage too; a second SIGINT ends a stage at
// once (cli/stage_main.cpp), so the test failed whenever the two arrived
// apart (seen once in a loaded `make test`).
TEST(PlanStage, AnInterruptedRunWritesNothingAndExits130) {
  const auto yaml = testing::MakeGeneratedScene("rod-in-cage", 1);
  const auto dir = yaml.parent_path();
  const Scene scene = LoadScene(yaml);
  TriangleMesh closed = scene.static_mesh;
  const Aabb box = closed.Bounds();
  closed.Append(MakeBox({box.min.x(), box.min.y(), box.max.z() - 1.0}, box.max));  // a solid lid: no way out
  SaveObj(closed, dir / "environment.obj");
  WriteFile(dir / "p.h5", "what was there before");
  const Outcome plan = testing::RunStageCommand("plan",
                                                "--scene " + yaml.string() + " --time-limit 60 --force -o " +
                                                    (dir / "p.h5").string() + " --csv " + (dir / "p.csv").string(),
                                                "timeout --foreground --preserve-status -s INT 3");
  EXPECT_EQ(plan.exit_code, 130) << plan.output;
  EXPECT_NE(plan.output.find("ausbau-plan: cancelled; no output written"), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find("ausbau-plan: planning 0% ("), std::string::npos) << "no progress line: " << plan.output;
  EXPECT_EQ(plan.output.find("no path within the budget"), std::string::npos) << plan.output;
  EXPECT_EQ(ReadFile(dir / "p.h5"), "what was there before");
  EXPECT_FALSE(std::filesystem::exists(dir / "p.csv"));
}

// A mistyped flag or scene key is refused with the name it was probably
// meant to be.
TEST(StageRunner, UnknownFlagsAndKeysSayWhatWasMeant) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  const Outcome flag = RunStage("plan", "--scene " + yaml.string() + " --time-limt 5");
  EXPECT_EQ(flag.exit_code, 2);
  ExpectOneLineError(flag, "plan", "--time-limt: unknown flag (did you mean --time-limit? see --help)");
  std::string text = ReadFile(yaml);
  text += "unts: mm\n";
  WriteFile(yaml, text);
  const Outcome key = RunStage("plan", "--scene " + yaml.string());
  EXPECT_EQ(key.exit_code, 2);
  ExpectOneLineError(key, "plan", "unknown key 'unts' (line ");
  ExpectOneLineError(key, "plan", "did you mean 'units'?");
}

class BadSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    yaml_ = testing::MakeGeneratedScene("two-boxes", 1);
    text_ = ReadFile(yaml_);
  }
  // Replaces the first line starting with `key` by `line`.
  void ReplaceLine(const std::string& key, const std::string& line) {
    std::istringstream in(text_);
    std::string result, current;
    bool replaced = false;
    while (std::getline(in, current)) {
      if (!replaced && current.rfind(key, 0) == 0) {
        current = line;
        replaced = true;
      }
      result += current + "\n";
    }
    ASSERT_TRUE(replaced) << key;
    WriteFile(yaml_, result);
  }
  Outcome Plan() {
    return RunStage("plan", "--scene " + yaml_.string() + " -o " + (yaml_.parent_path() / "p.h5").string());
  }

  std::filesystem::path yaml_;
  std::string text_;
};

TEST_F(BadSceneTest, MissingSceneFile) {
  const Outcome o = RunStage("plan", "--scene /nonexistent/scene.yaml");
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "/nonexistent/scene.yaml: file not found");
}

TEST_F(BadSceneTest, UnknownKey) {
  WriteFile(yaml_, text_ + "colour: red\n");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "unknown key 'colour'");
}

TEST_F(BadSceneTest, NonUnitQuaternion) {
  ReplaceLine("start:", "start: {t: [-3, 0, 0], q: [1, 1, 0, 0]}");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "not a unit quaternion");
}

TEST_F(BadSceneTest, MalformedQuaternion) {
  ReplaceLine("start:", "start: {t: [-3, 0, 0], q: [1, 0, 0]}");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "start.q");
}

TEST_F(BadSceneTest, StartOutsideBounds) {
  ReplaceLine("start:", "start: {t: [-30, 0, 0], q: [1, 0, 0, 0]}");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "outside bounds");
}

TEST_F(BadSceneTest, GoalInCollision) {
  ReplaceLine("goal:", "goal: {t: [1.2, 0, 0], q: [1, 0, 0, 0]}");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "goal pose is in collision");
}

TEST_F(BadSceneTest, MissingMesh) {
  std::filesystem::remove(yaml_.parent_path() / "part.obj");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "part.obj: file not found");
}

TEST_F(BadSceneTest, EmptyMesh) {
  WriteFile(yaml_.parent_path() / "part.obj", "v 0 0 0\nv 1 0 0\n");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "no triangles");
}

TEST_F(BadSceneTest, NanVertex) {
  WriteFile(yaml_.parent_path() / "part.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  const Outcome o = Plan();
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "not finite");
}

TEST(PlanStage, BadOptionsAreUsageErrors) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  Outcome o = RunStage("plan", "--scene " + yaml.string() + " --planner nope");
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "plan", "unknown planner 'nope'");
  o = RunStage("plan", "--scene " + yaml.string() + " --time-limit -5");
  EXPECT_EQ(o.exit_code, 2);
  o = RunStage("plan", "--bogus");
  EXPECT_EQ(o.exit_code, 2);
  o = RunStage("plan", "--help");
  EXPECT_EQ(o.exit_code, 0);
  EXPECT_NE(o.output.find("--scene"), std::string::npos);
}

// The benchmarks answer like the stages: --help and --version exit 0 (and
// do no work), a bad flag or value exits 2.
TEST(Benchmarks, HelpVersionAndBadFlagsExitLikeTheStages) {
  for (const char* bench : {"farr-bench", "inistate-bench", "label-bench", "nn-bench"}) {
    SCOPED_TRACE(bench);
    Outcome o = RunStage(bench, "--version");
    EXPECT_EQ(o.exit_code, 0) << o.output;
    EXPECT_EQ(o.output, std::string(AUSBAU_VERSION) + "\n");
    o = RunStage(bench, "--help");
    EXPECT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("Usage: ausbau-"), std::string::npos) << o.output;
    o = RunStage(bench, "--bogus");
    EXPECT_EQ(o.exit_code, 2) << o.output;
  }
  const Outcome o = RunStage("nn-bench", "--queries 0");
  EXPECT_EQ(o.exit_code, 2) << o.output;
}

// --threads is bounded everywhere (OpenMP crashed on 100000 and read -1 as
// huge), and so are --seed, --time-limit and --tau (-1 wrapped to 2^64 - 1,
// 1e308 s overflowed the deadline, -5 meant "estimate"): a usage error
// naming the flag, before any work.
TEST(Stages, ThreadsSeedsTimeLimitsAndTauOutOfRangeAreUsageErrors) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  for (const char* stage : {"voxelize", "medial-spheres", "pbd-label", "distfield-build", "plan", "tau-estimate"}) {
    for (const char* threads : {"-1", "100000"}) {
      SCOPED_TRACE(std::string(stage) + " --threads " + threads);
      const Outcome o = RunStage(stage, "--scene " + yaml.string() + " --threads " + threads);
      EXPECT_EQ(o.exit_code, 2) << o.output;
      ExpectOneLineError(o, stage, "--threads: must lie in 0 .. 1024, got " + std::string(threads));
    }
  }
  // Values that used to wrap or overflow silently.
  Outcome o = RunStage("plan", "--scene " + yaml.string() + " --seed -1");
  EXPECT_EQ(o.exit_code, 2) << o.output;
  ExpectOneLineError(o, "plan", "--seed: must lie in 0 .. ");
  o = RunStage("plan", "--scene " + yaml.string() + " --time-limit 1e308");
  EXPECT_EQ(o.exit_code, 2) << o.output;
  ExpectOneLineError(o, "plan", "--time-limit: must lie in 0.001 .. 604800, got 1e308");
  o = RunStage("plan", "--scene " + yaml.string() + " --tau -5");
  EXPECT_EQ(o.exit_code, 2) << o.output;
  ExpectOneLineError(o, "plan", "--tau: must lie in 0 .. ");
  o = RunStage("tau-estimate", "--scene " + yaml.string() + " --seed -2");
  EXPECT_EQ(o.exit_code, 2) << o.output;
  o = RunStage("smooth", "--scene " + yaml.string() + " --path x.h5 --time-limit 0");
  EXPECT_EQ(o.exit_code, 2) << o.output;
  for (const char* bench : {"farr-bench", "inistate-bench", "label-bench"}) {
    EXPECT_EQ(RunStage(bench, "--threads -1").exit_code, 2) << bench;
  }
}

TEST(SmoothStage, RejectsAFileThatIsNotAPathArtifact) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  Outcome o = RunStage("smooth", "--scene " + yaml.string() + " --path " + yaml.string());
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "smooth", "not a readable HDF5 file");
  o = RunStage("smooth", "--scene " + yaml.string() + " --path /nonexistent.h5");
  EXPECT_EQ(o.exit_code, 2);
  ExpectOneLineError(o, "smooth", "file not found");
}

TEST(SceneGenStage, WritesALoadableScene) {
  const auto dir = testing::MakeTempDir("scene-gen");
  const Outcome o = RunStage("scene-gen", "--family peg-in-plate -o " + dir.string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NO_THROW(LoadScene(dir / "scene.yaml"));
  EXPECT_EQ(RunStage("scene-gen", "--family nope -o " + dir.string()).exit_code, 2);
}

// The families by name (fixtures/scene_families.h): each list's family has
// its kind, the names list every family, and the library writes a scene and
// says which file, or refuses an unknown family.
TEST(SceneFamilies, KindsNamesAndGeneration) {
  EXPECT_EQ(KindOfSceneFamily("rod-in-cage"), SceneFamilyKind::kGenerated);
  EXPECT_EQ(KindOfSceneFamily("clips-ds3"), SceneFamilyKind::kClip);
  EXPECT_EQ(KindOfSceneFamily("panel-channel"), SceneFamilyKind::kBox);
  EXPECT_EQ(KindOfSceneFamily("vehicle"), SceneFamilyKind::kVehicle);
  EXPECT_EQ(KindOfSceneFamily("clips-ds9"), SceneFamilyKind::kUnknown);
  const std::string names = SceneFamilyNames();
  for (const char* family : {"rod-in-cage", "two-boxes", "clips-ds1", "clips-ds5", "panel-tilt-slide", "vehicle"}) {
    EXPECT_NE(names.find(family), std::string::npos) << family << " in " << names;
  }
  const auto dir = testing::MakeTempDir("scene-families");
  SceneFamilyOptions options;
  options.family = "two-boxes";
  const std::vector<std::string> lines = GenerateSceneFamily(options, dir);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], (dir / "scene.yaml").string());
  EXPECT_NO_THROW(LoadScene(lines[0]));
  options.family = "nope";
  EXPECT_THROW(GenerateSceneFamily(options, dir / "nope"), InputError);
}

// --validity and --collision are parsed into enums, but the provenance keeps
// their spelling: --validate's hash of the default equals that of the
// default given by name, and differs from another mode's.
TEST(StageRunner, ModesKeepTheirSpellingInTheProvenance) {
  const auto scene = testing::MakeGeneratedScene("two-boxes", 1).string();
  const auto hash = [&](const std::string& flags) {
    const Outcome o = RunStage("plan", "--scene " + scene + " --validate" + flags);
    EXPECT_EQ(o.exit_code, 0) << o.output;
    const auto at = o.output.find("provenance");
    return at == std::string::npos ? o.output : o.output.substr(at);
  };
  EXPECT_EQ(hash(""), hash(" --validity collision --collision fcl"));
  EXPECT_NE(hash(""), hash(" --validity rigid-exact"));
  EXPECT_NE(hash(""), hash(" --collision farr"));
  const Outcome bad = RunStage("plan", "--scene " + scene + " --validity exact");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--validity"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("rigid-exact,collision,shrink"), std::string::npos) << bad.output;
}

// The `inputs` of an artifact: role -> content hash.
std::map<std::string, std::string> ArtifactInputs(const std::filesystem::path& file, const std::string& schema,
                                                  int schema_version) {
  const ArtifactReader reader(file, schema, schema_version);
  std::map<std::string, std::string> inputs;
  for (const auto& entry : YAML::Load(reader.ReadStringAttribute("", "inputs"))) {
    inputs[entry.first.as<std::string>()] = entry.second.as<std::string>();
  }
  return inputs;
}

// scene.yaml's `static:` may list several files. Each must be an input of its
// own: they once all had the role "static", and every stage that writes an
// artifact failed at the end with "duplicate input role 'static'". A change to
// the second file must invalidate the stages' outputs.
TEST(SceneInputs, EachOfSeveralStaticFilesIsAnInputOfEveryStage) {
  const auto yaml = testing::MakeGeneratedScene("two-boxes", 1);
  const auto dir = yaml.parent_path();
  struct Stage {
    std::string name, arguments, output, schema;
    int schema_version;
  };
  const std::string scene = "--scene " + yaml.string();
  const std::vector<Stage> stages = {
      {"voxelize", scene + " --voxel-size 0.05 --threads 1", "voxels.h5", kVoxelsSchema, kVoxelsSchemaVersion},
      {"plan", scene + " --validity collision --threads 1", "path.h5", kPathSchema, kPathSchemaVersion},
      {"smooth", scene + " --path " + (dir / "path.h5").string(), "smooth.h5", kPathSchema, kPathSchemaVersion},
      {"tau-estimate", scene + " --validity iv --voxels " + (dir / "voxels.h5").string() + " --threads 1 --rounds 1",
       "tau.h5", kTauSchema, kTauSchemaVersion},
  };
  // Runs every stage; returns each output's provenance hash.
  const auto run_all = [&](bool expect_up_to_date) {
    std::vector<std::string> hashes;
    for (const Stage& stage : stages) {
      const Outcome o = RunStage(stage.name, stage.arguments + " -o " + (dir / stage.output).string());
      EXPECT_EQ(o.exit_code, 0) << stage.name << ": " << o.output;
      EXPECT_EQ(o.output.find("up to date") != std::string::npos, expect_up_to_date) << stage.name << ": " << o.output;
      hashes.push_back(ExistingProvenanceHash(dir / stage.output, stage.schema, stage.schema_version).value_or(""));
    }
    return hashes;
  };

  // One static file keeps the role "static", so earlier outputs stay valid.
  const Outcome one = RunStage("voxelize", stages[0].arguments + " -o " + (dir / "voxels.h5").string());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  auto inputs = ArtifactInputs(dir / "voxels.h5", kVoxelsSchema, kVoxelsSchemaVersion);
  EXPECT_EQ(inputs["static"], HashFile(dir / "environment.obj"));
  EXPECT_EQ(inputs.count("static[0]"), 0u);

  // A second static file, away from D's way.
  SaveObj(MakeBox({3.5, 3.5, 3.5}, {4.5, 4.5, 4.5}), dir / "extra.obj");
  std::string text = ReadFile(yaml);
  const std::string line = "static: [\"environment.obj\"]";
  const auto at = text.find(line);
  ASSERT_NE(at, std::string::npos) << text;
  WriteFile(yaml, text.replace(at, line.size(), "static: [\"environment.obj\", \"extra.obj\"]"));
  ASSERT_EQ(LoadScene(yaml).static_files.size(), 2u);

  const std::vector<std::string> before = run_all(false);
  if (::testing::Test::HasFailure()) return;
  for (const Stage& stage : stages) {
    inputs = ArtifactInputs(dir / stage.output, stage.schema, stage.schema_version);
    EXPECT_EQ(inputs.count("static"), 0u) << stage.name;
    EXPECT_EQ(inputs["static[0]"], HashFile(dir / "environment.obj")) << stage.name;
    EXPECT_EQ(inputs["static[1]"], HashFile(dir / "extra.obj")) << stage.name;
    EXPECT_EQ(inputs["dynamic"], HashFile(dir / "part.obj")) << stage.name;
  }
  EXPECT_EQ(run_all(true), before);

  // Only the second file changes: every output is computed again.
  SaveObj(MakeBox({3.5, 3.5, 3.5}, {4.6, 4.5, 4.5}), dir / "extra.obj");
  const std::vector<std::string> after = run_all(false);
  for (std::size_t i = 0; i < stages.size(); ++i) {
    EXPECT_NE(after[i], before[i]) << stages[i].name;
    inputs = ArtifactInputs(dir / stages[i].output, stages[i].schema, stages[i].schema_version);
    EXPECT_EQ(inputs["static[1]"], HashFile(dir / "extra.obj")) << stages[i].name;
  }
}

}  // namespace
}  // namespace ausbau
