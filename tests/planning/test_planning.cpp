// Planners on small generated scenes, each path re-checked densely with the
// independent checker; nearest neighbours against brute force; smoothing.
#include <gtest/gtest.h>
#include <atomic>
#include <cstdio>
#include <fstream>

#include "collision/fcl_checker.h"
#include "collision/rigid_depth.h"
#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/error.h"
#include "fixtures/box_scenes.h"
#include "generated_scene.h"
#include "geometry/primitives.h"
#include "planning/certify.h"
#include "planning/dense_check.h"
#include "planning/nearest_neighbors.h"
#include "planning/planner.h"
#include "planning/prm.h"
#include "planning/sampler.h"
#include "planning/smoother.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "test_bar_in_channel.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

struct Fixture {
  explicit Fixture(const std::string& family, std::uint64_t seed = 1)
      : scene(LoadScene(testing::MakeGeneratedScene(family, seed))),
        problem(MakePlanningProblem(scene)),
        checker(problem.robot, problem.environment) {}
  std::vector<Pose> ToScene(const std::vector<Pose>& path) const {
    std::vector<Pose> out;
    for (const Pose& p : path) out.push_back(problem.PlanningToScene(p));
    return out;
  }
  Scene scene;
  PlanningProblem problem;
  FclCollisionChecker checker;
};

// One planner run with the default options and `seed`.
PlanResult PlanWithSeed(const Fixture& f, std::uint64_t seed) {
  PlannerOptions options;
  options.seed = seed;
  return Plan(f.problem, f.checker, options);
}

// Four times finer than the acceptance criterion (1% of D's diagonal).
constexpr double kDenseStep = 0.0025;

void ExpectValidPath(const Fixture& f, const std::vector<Pose>& path) {
  ASSERT_FALSE(path.empty());
  EXPECT_TRUE(path.front().t.isApprox(f.problem.start.t));
  if (f.problem.goal) {
    EXPECT_TRUE(path.back().t.isApprox(f.problem.goal->t, 1e-9));
    EXPECT_LT(RotationAngle(path.back().q, f.problem.goal->q), 1e-9);
  } else {
    EXPECT_TRUE(f.problem.InGoalRegion(path.back()));
  }
  const DenseCheckReport report = DenseCheckPath(f.scene, f.problem.reference_point, f.ToScene(path), kDenseStep);
  EXPECT_TRUE(report.valid) << "segment " << report.first_bad_segment << " at " << report.first_bad_fraction << ": "
                            << report.reason;
}

class PlannerOnScene : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(PlannerOnScene, SolvesAndThePathIsValid) {
  const auto& [planner, family] = GetParam();
  Fixture f(family);
  PlannerOptions options;
  options.planner = planner;
  options.seed = 5;
  options.time_limit_s = 120;  // generous: the result must not depend on timing
  const PlanResult result = Plan(f.problem, f.checker, options);
  ASSERT_TRUE(result.solved());
  EXPECT_GT(result.stats.iterations, 0);
  EXPECT_GE(result.stats.nodes, 2);
  EXPECT_GT(result.stats.collision_checks, 0);
  ExpectValidPath(f, result.path);
}

// Each planner on the scenes it is meant for. Left out on purpose (they do
// not solve them within minutes, which is what the thesis reports of fixed
// parameters and uniform sampling): Def-RRTC on peg-in-plate (its goal tree,
// rooted in the wide-open disassembly region, takes half of the iterations
// while the start tree is trapped in the 0.1-wide hole), RRT on peg-in-plate
// (about 40 s), EST on rod-in-cage (local expansion fills the cage before it
// finds the slot), PRM on peg-in-plate (uniform samples almost never fall
// into the hole).
INSTANTIATE_TEST_SUITE_P(Scenes, PlannerOnScene,
                         ::testing::Values(std::make_tuple("rrtc", "two-boxes"), std::make_tuple("rrtc", "rod-in-cage"),
                                           std::make_tuple("cr-rrtc", "two-boxes"),
                                           std::make_tuple("cr-rrtc", "peg-in-plate"),
                                           std::make_tuple("cr-rrtc", "rod-in-cage"),
                                           std::make_tuple("rrt", "two-boxes"), std::make_tuple("est", "peg-in-plate"),
                                           std::make_tuple("prm", "two-boxes")),
                         [](const auto& info) {
                           std::string name = std::get<0>(info.param) + "_" + std::get<1>(info.param);
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

// The second try of a trapped extension along the nearby nodes' principal
// directions (planning/passage_direction.h) gets CR-RRTC's start tree out of
// peg-in-plate's hole sooner: over seeds 1-6, 18,565 iterations in all
// against 31,642 without it (fewer on 5 of the 6 seeds). Every path valid.
TEST(Planner, TheSecondTryAlongThePassageLeadsOutOfAHoleSooner) {
  Fixture f("peg-in-plate");
  std::int64_t with_iterations = 0, without_iterations = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    PlannerOptions options;
    options.seed = seed;
    options.max_iterations = 40000;
    options.time_limit_s = 120;  // generous: the result must not depend on timing
    const PlanResult with = Plan(f.problem, f.checker, options);
    ASSERT_TRUE(with.solved()) << "seed " << seed;
    ExpectValidPath(f, with.path);
    options.passage_neighbors = 0;
    const PlanResult without = Plan(f.problem, f.checker, options);
    ASSERT_TRUE(without.solved()) << "seed " << seed;
    with_iterations += with.stats.iterations;
    without_iterations += without.stats.iterations;
  }
  std::printf("peg-in-plate, cr-rrtc, seeds 1-6: %lld iterations with the second try, %lld without\n",
              static_cast<long long>(with_iterations), static_cast<long long>(without_iterations));
  EXPECT_LT(with_iterations, without_iterations);
}

// Exit moves (planning/rrt_connect.h): a key in a keyhole slot
// (panel-keyhole seed 2: slide 40 mm, turn a quarter, lift through an
// opening 0.23 mm around the turned bit) comes out within 10,000 iterations
// with them and not without them (then about 190,000 in 60 s were not
// enough). A goal pose (two-boxes) leaves them out: the same run.
TEST(Planner, ExitMovesTurnAKeyAndLiftItOut) {
  BoxSceneOptions box;
  box.seed = 2;
  box.world = BoxWorld::kRandom;
  const auto yaml = GenerateBoxScene("panel-keyhole", box, testing::MakeTempDir("panel-keyhole-2")).scene_yaml;
  const Scene scene = LoadScene(yaml);
  const PlanningProblem problem = MakePlanningProblem(scene);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  PlannerOptions options;
  options.seed = 2;
  options.max_iterations = 10000;
  options.time_limit_s = 300;  // generous: the result must not depend on timing
  options.exit_axes = 1;
  const PlanResult with = Plan(problem, checker, options);
  ASSERT_TRUE(with.solved());
  std::vector<Pose> scene_path;
  for (const Pose& p : with.path) scene_path.push_back(problem.PlanningToScene(p));
  EXPECT_TRUE(problem.InGoalRegion(with.path.back()));
  EXPECT_TRUE(DenseCheckPath(scene, problem.reference_point, scene_path, kDenseStep).valid);
  options.exit_axes = 0;
  const PlanResult without = Plan(problem, checker, options);
  EXPECT_FALSE(without.solved());
  std::printf(
      "panel-keyhole-s2, cr-rrtc seed 2: solved after %lld iterations with exit moves; not within %lld "
      "without\n",
      static_cast<long long>(with.stats.iterations), static_cast<long long>(without.stats.iterations));

  Fixture f("two-boxes");  // a goal pose
  PlannerOptions goal_options;
  goal_options.exit_axes = 1;
  const PlanResult a = Plan(f.problem, f.checker, goal_options);
  goal_options.exit_axes = 0;
  const PlanResult b = Plan(f.problem, f.checker, goal_options);
  ASSERT_TRUE(a.solved());
  EXPECT_EQ(a.stats.iterations, b.stats.iterations);
  EXPECT_EQ(a.stats.collision_checks, b.stats.collision_checks);
}

// Bit for bit the same poses.
void ExpectSamePath(const std::vector<Pose>& a, const std::vector<Pose>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].t, b[i].t);
    EXPECT_EQ(a[i].q.coeffs(), b[i].q.coeffs());
  }
}

// A search at a step coarser than D is thin (--resolution 0.04: 4% of its
// diagonal) passes through a wall thinner still: D, a plate
// 10 x 10 x 0.02, kept flat (translation only), from below a wall 60 x 60 x
// 0.02 to above it; the bounds leave room around the wall's edges. The path
// returned is certified at a quarter of a percent of D's diagonal, so it
// goes around the wall (repaired, or searched again at 1%), for every seed.
TEST(Planner, ACoarseSearchThroughAThinWallReturnsAPathAroundIt) {
  const std::filesystem::path dir = testing::MakeTempDir("thin-wall");
  SaveObj(MakeBox(Eigen::Vector3d(-30, -30, -0.01), Eigen::Vector3d(30, 30, 0.01)), dir / "wall.obj");
  SaveObj(MakeBox(Eigen::Vector3d(-5, -5, -0.01), Eigen::Vector3d(5, 5, 0.01)), dir / "plate.obj");
  std::ofstream(dir / "scene.yaml") << "format: ausbau-scene/1\nunits: mm\nstatic: [wall.obj]\ndynamic: plate.obj\n"
                                    << "dynamic_origin: [0, 0, 0]\nstart: {t: [0, 0, -5.25]}\n"
                                    << "goal: {t: [0, 0, 5.25], q: [1, 0, 0, 0]}\n"
                                    << "bounds: {min: [-40, -40, -10], max: [40, 40, 10]}\n";
  const Scene scene = LoadScene(dir / "scene.yaml");
  PlanningProblem problem = MakePlanningProblem(scene);
  problem.fixed_rotation = Eigen::Quaterniond::Identity();
  const FclCollisionChecker checker(problem.robot, problem.environment);
  // The scene is what it says: the straight motion start -> goal is valid
  // at 4% of D's diagonal and not at the certification's step.
  const double coarse = 0.04 * problem.robot_diagonal;
  EXPECT_TRUE(MotionChecker(problem, checker, coarse).MotionValid(problem.start, *problem.goal));
  EXPECT_DOUBLE_EQ(CertificationStep(problem, coarse), kCertificationResolution * problem.robot_diagonal);
  EXPECT_DOUBLE_EQ(CertificationStep(problem, 0.004 * problem.robot_diagonal), 0.001 * problem.robot_diagonal);
  EXPECT_FALSE(
      MotionChecker(problem, checker, CertificationStep(problem, coarse)).MotionValid(problem.start, *problem.goal));
  // Both ways of searching at 4%: asked for, and ausbau-plan's coarse
  // first search ahead of one at 1%.
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    for (const bool coarse_first : {false, true}) {
      PlannerOptions options;
      options.seed = seed;
      options.resolution = coarse_first ? 0.01 : 0.04;
      options.coarse_iterations = coarse_first ? kCoarseFirstIterations : 0;
      options.time_limit_s = 120;  // generous: the result must not depend on timing
      const PlanResult result = Plan(problem, checker, options);
      ASSERT_TRUE(result.solved()) << "seed " << seed;
      std::vector<Pose> scene_path;
      double farthest = 0;  // from the wall's centre line, in x or y
      for (const Pose& pose : result.path) {
        scene_path.push_back(problem.PlanningToScene(pose));
        farthest = std::max(farthest, pose.t.head<2>().cwiseAbs().maxCoeff());
      }
      const DenseCheckReport dense = DenseCheckPath(scene, problem.reference_point, scene_path, kDenseStep);
      EXPECT_TRUE(dense.valid) << "seed " << seed << ": " << dense.reason;
      EXPECT_GT(farthest, 35.0) << "seed " << seed << ": the path does not go around the wall";
    }
  }
}

// The coarse first search that finds nothing in its iterations hands over
// to the search at 1%, which starts afresh with the same seed: the same
// path as that search alone, after one more iteration (here the coarse
// search gets one, too few for the rod to leave its cage).
TEST(Planner, ACoarseFirstSearchWithoutAPathHandsOverToTheFineSearch) {
  Fixture f("rod-in-cage");
  PlannerOptions options;
  options.seed = 9;
  options.time_limit_s = 120;  // generous: the result must not depend on timing
  const PlanResult fine_only = Plan(f.problem, f.checker, options);
  ASSERT_TRUE(fine_only.solved());
  ASSERT_GT(fine_only.stats.iterations, 1);
  options.coarse_iterations = 1;
  const PlanResult handed_over = Plan(f.problem, f.checker, options);
  ASSERT_TRUE(handed_over.solved());
  ExpectSamePath(fine_only.path, handed_over.path);
  EXPECT_EQ(handed_over.stats.iterations, fine_only.stats.iterations + 1);
  EXPECT_GT(handed_over.stats.collision_checks, fine_only.stats.collision_checks);
  // An iteration cap covers both searches together.
  options.coarse_iterations = 2;
  options.max_iterations = 3;
  const PlanResult capped = Plan(f.problem, f.checker, options);
  EXPECT_EQ(capped.status, PlanStatus::kIterationLimit);
  EXPECT_EQ(capped.stats.iterations, 3);
  // A step asked for at 4% or coarser has no coarse first search.
  options.max_iterations = 0;
  options.coarse_iterations = 1;
  options.resolution = kCoarseResolution;
  PlannerOptions plain = options;
  plain.coarse_iterations = 0;
  const PlanResult at_coarse_step = Plan(f.problem, f.checker, plain);
  const PlanResult asked_coarse = Plan(f.problem, f.checker, options);
  ASSERT_TRUE(at_coarse_step.solved());
  ExpectSamePath(at_coarse_step.path, asked_coarse.path);
  EXPECT_EQ(at_coarse_step.stats.iterations, asked_coarse.stats.iterations);
}

TEST(Planner, SameSeedSamePath) {
  Fixture f("rod-in-cage");
  PlannerOptions options;
  options.seed = 9;
  const PlanResult a = Plan(f.problem, f.checker, options);
  const PlanResult b = Plan(f.problem, f.checker, options);
  ASSERT_TRUE(a.solved());
  ExpectSamePath(a.path, b.path);
  EXPECT_EQ(a.stats.iterations, b.stats.iterations);
  options.seed = 10;
  const PlanResult c = Plan(f.problem, f.checker, options);
  EXPECT_NE(a.stats.iterations, c.stats.iterations);
}

TEST(Planner, IterationLimitIsAnOutcomeNotAnError) {
  Fixture f("rod-in-cage");
  PlannerOptions options;
  options.max_iterations = 3;
  const PlanResult result = Plan(f.problem, f.checker, options);
  EXPECT_EQ(result.status, PlanStatus::kIterationLimit);
  EXPECT_TRUE(result.path.empty());
  EXPECT_EQ(result.stats.iterations, 3);
}

TEST(Planner, RestartsSolveAndAnIterationCapIsOneRound) {
  Fixture f("rod-in-cage");
  PlannerOptions options;
  options.seed = 9;
  options.time_limit_s = 60;
  const PlanResult restarted = PlanWithRestarts(f.problem, f.checker, options);
  ASSERT_TRUE(restarted.solved());
  EXPECT_GT(restarted.stats.iterations, 0);
  // With an iteration cap there are no rounds: the same run as Plan().
  options.max_iterations = 3;
  const PlanResult capped = PlanWithRestarts(f.problem, f.checker, options);
  EXPECT_EQ(capped.status, PlanStatus::kIterationLimit);
  EXPECT_EQ(capped.stats.iterations, 3);
}

// Issue 30: a work budget over all restart rounds (the rigid-exact crop
// levels): the rounds stop when they have used it together, with
// kIterationLimit, the last round capped to the rest; deterministic.
TEST(Planner, ATotalIterationBudgetEndsTheRestartsExactly) {
  Fixture f("rod-in-cage");
  PlannerOptions options;
  options.seed = 9;
  options.time_limit_s = 600;           // the safety net: never reached here
  options.max_total_iterations = 5000;  // one round of 4096, then 904
  const PlanResult capped = PlanWithRestarts(f.problem, f.checker, options);
  if (capped.solved()) {
    EXPECT_LE(capped.stats.iterations, 5000);
  } else {
    EXPECT_EQ(capped.status, PlanStatus::kIterationLimit);
    EXPECT_EQ(capped.stats.iterations, 5000);
  }
  const PlanResult again = PlanWithRestarts(f.problem, f.checker, options);
  EXPECT_EQ(again.status, capped.status);
  EXPECT_EQ(again.stats.iterations, capped.stats.iterations);
  // A tiny budget that no round solves in.
  options.max_total_iterations = 2;
  const PlanResult tiny = PlanWithRestarts(f.problem, f.checker, options);
  EXPECT_EQ(tiny.status, PlanStatus::kIterationLimit);
  EXPECT_EQ(tiny.stats.iterations, 2);
}

// A raised cancel flag stops every planner at its next iteration (the tau
// estimate cancels speculative rounds this way).
TEST(Planner, CancelFlagStopsThePlanner) {
  Fixture f("rod-in-cage");
  const std::atomic<bool> cancel{true};
  for (const char* planner : {"rrt", "rrtc", "cr-rrtc", "est", "prm"}) {
    SCOPED_TRACE(planner);
    PlannerOptions options;
    options.planner = planner;
    options.cancel = &cancel;
    const PlanResult result = Plan(f.problem, f.checker, options);
    EXPECT_EQ(result.status, PlanStatus::kCancelled);
    EXPECT_TRUE(result.path.empty());
    EXPECT_LT(result.stats.time_s, 5.0);
  }
}

// The process-wide flag (core/cancel.h, raised by the stage runner on
// SIGINT) stops every planner the same way; the callers that turn a search
// into an answer (restarts, straight pulls) throw Cancelled instead of
// reporting "no path", and nothing is committed to disk afterwards.
TEST(Planner, ProcessWideCancelStopsPlannersAndIsNoAnswer) {
  Fixture f("rod-in-cage");
  RequestCancel();
  for (const char* planner : {"rrt", "rrtc", "cr-rrtc", "est", "prm"}) {
    SCOPED_TRACE(planner);
    PlannerOptions options;
    options.planner = planner;
    const PlanResult result = Plan(f.problem, f.checker, options);
    EXPECT_EQ(result.status, PlanStatus::kCancelled);
    EXPECT_TRUE(result.path.empty());
  }
  PlannerOptions options;
  EXPECT_THROW(PlanWithRestarts(f.problem, f.checker, options), Cancelled);
  EXPECT_THROW(TryStraightPulls(f.problem, f.checker, options), Cancelled);
  const testing::ScopedTempDir dir("cancel");
  const auto file = dir / "cancel-test.txt";
  ResetCancel();
  WriteTextFileAtomically(file, "before");
  RequestCancel();
  EXPECT_THROW(WriteTextFileAtomically(file, "after"), Cancelled);
  ResetCancel();
  EXPECT_EQ(testing::ReadTextFile(file), "before");
}

// The progress callback reports iterations against the limit, and whether
// it is given changes nothing in the answer.
TEST(Planner, ProgressIsReportedAndChangesNothing) {
  Fixture f("rod-in-cage");
  PlannerOptions options;
  options.seed = 4;
  options.max_iterations = 200000;
  const PlanResult silent = Plan(f.problem, f.checker, options);
  std::int64_t calls = 0, last_total = -1;
  options.progress = [&](std::int64_t, std::int64_t total) {
    ++calls;
    last_total = total;
  };
  const PlanResult reported = Plan(f.problem, f.checker, options);
  ASSERT_TRUE(silent.solved());
  ExpectSamePath(reported.path, silent.path);
  EXPECT_EQ(reported.stats.iterations, silent.stats.iterations);
  EXPECT_GE(calls, 1);  // the first iteration reports
  EXPECT_EQ(last_total, 200000);
}

TEST(Planner, RejectsBadOptions) {
  PlannerOptions options;
  options.planner = "nope";
  EXPECT_THROW(options.Check(), InputError);
  options = PlannerOptions();
  options.u = 1.5;
  EXPECT_THROW(options.Check(), InputError);
  options = PlannerOptions();
  options.time_limit_s = -1;
  EXPECT_THROW(options.Check(), InputError);
}

TEST(Planner, CollidingEndpointsAreInputErrors) {
  Fixture f("two-boxes");
  PlanningProblem problem = f.problem;
  problem.goal->t = {1.0, 0, 0};
  EXPECT_THROW(CheckEndpoints(problem, f.checker, "scene.yaml"), InputError);
  problem = f.problem;
  problem.start.t = {1.0, 0, 0};
  EXPECT_THROW(CheckEndpoints(problem, f.checker, "scene.yaml"), InputError);
  EXPECT_NO_THROW(CheckEndpoints(f.problem, f.checker, "scene.yaml"));
}

TEST(NearestNeighbors, EqualsBruteForceUnderRandomWeights) {
  Metric metric{25.0};
  NearestNeighbors index(metric);
  Random random(1);
  std::vector<Pose> poses;
  for (int i = 0; i < 2000; ++i) {
    Pose p;
    p.t = {random.Uniform(-10, 10), random.Uniform(-10, 10), random.Uniform(-10, 10)};
    p.q = random.UniformQuaternion();
    poses.push_back(p);
    index.Add(p);
  }
  for (int query = 0; query < 300; ++query) {
    Pose q;
    q.t = {random.Uniform(-12, 12), random.Uniform(-12, 12), random.Uniform(-12, 12)};
    q.q = random.UniformQuaternion();
    const double u = random.UniformOpen01();
    int best = -1;
    double best_distance = 1e300;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const double d = metric.Distance(poses[i], q, u);
      if (d < best_distance) best_distance = d, best = static_cast<int>(i);
    }
    const int found = index.Nearest(q, u);
    EXPECT_NEAR(metric.Distance(poses[found], q, u), best_distance, 1e-12) << "query " << query;
    EXPECT_EQ(found, best);
  }
}

TEST(Smoother, ShortensAndStaysValid) {
  Fixture f("rod-in-cage");
  const PlanResult plan = PlanWithSeed(f, 3);
  ASSERT_TRUE(plan.solved());
  SmoothOptions smooth;
  smooth.seed = 3;
  const SmoothResult result = SmoothPath(f.problem, f.checker, plan.path, smooth);
  EXPECT_LE(result.after.normalized, result.before.normalized + 1e-12);
  EXPECT_LE(result.path.size(), plan.path.size() + result.shortcuts);
  EXPECT_TRUE(result.path.front().t.isApprox(plan.path.front().t));
  // A disassembly's end may move (a straight retreat), but stays out of S.
  ASSERT_FALSE(f.problem.goal.has_value());
  EXPECT_TRUE(f.problem.InGoalRegion(result.path.back()));
  ExpectValidPath(f, result.path);
  // Deterministic.
  const SmoothResult again = SmoothPath(f.problem, f.checker, plan.path, smooth);
  ASSERT_EQ(again.path.size(), result.path.size());
  for (std::size_t i = 0; i < result.path.size(); ++i) EXPECT_EQ(again.path[i].t, result.path[i].t);
}

// Issue 30: the smoother's time limit is a safety net. Not reached, it
// changes nothing (the work is counted: no share of the time decides how
// many shortcuts run); reached, the result is marked cut short and is still
// a valid path from the start.
TEST(Smoother, TheTimeLimitIsOnlyASafetyNetAndSaysWhenItFires) {
  Fixture f("rod-in-cage");
  const PlanResult plan = PlanWithSeed(f, 3);
  ASSERT_TRUE(plan.solved());
  SmoothOptions smooth;
  smooth.seed = 3;
  smooth.time_limit_s = 600;
  const SmoothResult loose = SmoothPath(f.problem, f.checker, plan.path, smooth);
  EXPECT_FALSE(loose.cut_short);
  smooth.time_limit_s = 60;
  const SmoothResult tighter = SmoothPath(f.problem, f.checker, plan.path, smooth);
  EXPECT_FALSE(tighter.cut_short);
  EXPECT_EQ(tighter.attempts, loose.attempts);
  ASSERT_EQ(tighter.path.size(), loose.path.size());
  for (std::size_t i = 0; i < loose.path.size(); ++i) {
    EXPECT_EQ(tighter.path[i].t, loose.path[i].t);
    EXPECT_EQ(tighter.path[i].q.coeffs(), loose.path[i].q.coeffs());
  }
  smooth.time_limit_s = 1e-9;  // fires at once
  const SmoothResult cut = SmoothPath(f.problem, f.checker, plan.path, smooth);
  EXPECT_TRUE(cut.cut_short);
  EXPECT_TRUE(cut.path.front().t.isApprox(plan.path.front().t));
  ExpectValidPath(f, cut.path);
}

// A bar 2 x 2 x 40 in a channel whose walls it overlaps by 0.02 (with
// `bore`, a square bore: walls on all four sides), a floor 0.3 under it,
// checked as rigid-exact smooths (collision/rigid_depth.h: half the
// tolerance 0.05, new contacts collide). In contact, every retreat into a
// wall is blocked after one step (test_bar_in_channel.h).
struct BarInChannel {
  explicit BarInChannel(bool bore = false) : scene(testing::BarInChannelScene(40, 0.02, bore)) {}
  Scene scene;
  PlanningProblem problem = MakePlanningProblem(scene);
  RigidDepthChecker checker{ClassifyParts(problem.robot, problem.environment, problem.start, 0.05), 0.025, 0.0125,
                            NewContacts::kCollide};
};

// Motions from one pose that share its measured slack give MotionValid's
// answers; one into a wall it touches is decided by one check (the pose
// one step along, 0.1 into the wall), where MotionValid measures the start
// again and then walks by MinStep until the bar is too deep: two steps, as
// it may stay as deep as installed (0.02) plus a quarter of the tolerance
// (collision/rigid_depth.h PartModel::overlaps).
TEST(MotionChecker, MotionsFromOnePoseShareItsSlackAndGiveTheSameAnswers) {
  const BarInChannel f;
  const MotionChecker motion(f.problem, f.checker, 0.0025 * f.problem.robot_diagonal);
  const Pose& from = f.problem.start;
  const std::int64_t before_slack = f.checker.checks();
  const double slack = motion.StartSlack(from);
  ASSERT_GE(slack, 0);
  EXPECT_EQ(f.checker.checks(), before_slack + 1);
  int valid = 0, into_walls = 0;
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        if (x == 0 && y == 0 && z == 0) continue;
        Pose to = from;
        to.t += 10 * Eigen::Vector3d(x, y, z).normalized();
        std::int64_t checks = f.checker.checks();
        const bool answer = motion.MotionValidFrom(from, slack, to);
        const std::int64_t shared = f.checker.checks() - checks;
        checks = f.checker.checks();
        EXPECT_EQ(answer, motion.MotionValid(from, to)) << x << " " << y << " " << z;
        const std::int64_t alone = f.checker.checks() - checks;
        valid += answer;
        // Out along the walls (y) or up; into a wall or the floor: blocked.
        EXPECT_EQ(answer, x == 0 && z >= 0) << x << " " << y << " " << z;
        if (x != 0) {
          ++into_walls;
          EXPECT_EQ(shared, 1) << x << " " << y << " " << z;
          EXPECT_EQ(alone, 3) << x << " " << y << " " << z;
        }
      }
    }
  }
  EXPECT_EQ(valid, 5);
  EXPECT_EQ(into_walls, 18);
}

// A bar pulled straight up out of a channel (60): the channel is open
// along y, so the smoother's retreat leaves that way instead, a straight
// translation without turning. Out of a bore it can only go up: the path
// stays a straight pull, its end no farther, and the retreats the smoother
// tries (64 points along the path, 28 directions each) are blocked within
// the bore at one check each. Neither is cut short (their work is counted).
TEST(Smoother, AStraightPullInContactStaysAStraightTranslation) {
  const auto straight_pull = [](const BarInChannel& f) {
    Pose out = f.problem.start;
    out.t.z() += 60;
    EXPECT_TRUE(f.problem.InGoalRegion(out));
    EXPECT_TRUE(
        MotionChecker(f.problem, f.checker, 0.0025 * f.problem.robot_diagonal).MotionValid(f.problem.start, out));
    const SmoothResult result = SmoothPath(f.problem, f.checker, {f.problem.start, out}, SmoothOptions{});
    EXPECT_FALSE(result.cut_short);
    EXPECT_EQ(result.after.rotation, 0.0);
    EXPECT_TRUE(f.problem.InGoalRegion(result.path.back()));
    return result;
  };
  const BarInChannel channel;
  const SmoothResult sideways = straight_pull(channel);
  ASSERT_EQ(sideways.path.size(), 2u);
  const Eigen::Vector3d move = sideways.path[1].t - sideways.path[0].t;
  EXPECT_LT(std::abs(move.x()) + std::abs(move.z()), 1e-9) << move.transpose();
  EXPECT_LT(std::abs(move.y()), 10.0);  // out of S's box (+-5) along y, against 60 up

  const BarInChannel bore(true);
  const std::int64_t before = bore.checker.checks();
  const SmoothResult up = straight_pull(bore);
  const std::int64_t checks = bore.checker.checks() - before;
  for (const Pose& pose : up.path) EXPECT_LT((pose.t - bore.problem.start.t).head<2>().norm(), 1e-9);
  EXPECT_LE(up.after.translation, 60.0);
  // 891: about one per retreat tried; 1,703 when each measured its start
  // again and then the pose at its first step (MinStep along).
  EXPECT_LT(checks, 1000) << checks;
}

// Under a validity that measures slack (rigid-exact), a motion is walked
// by conservative advancement whatever the step: certification takes the
// path as planned and checks nothing again (a fine re-check walked the same
// poses and, on a long slide in contact, ran into the time limit).
TEST(Certify, APathUnderASlackValidityIsCertifiedAsPlannedWithoutCheckingAgain) {
  const BarInChannel f(true);
  Pose out = f.problem.start;
  out.t.z() += 60;
  std::vector<Pose> path = {f.problem.start, out};
  const std::int64_t before = f.checker.checks();
  const CertifyReport report = CertifyPath(f.problem, f.checker, 1e-4, PlannerOptions{}, &path);
  EXPECT_TRUE(report.certified);
  EXPECT_EQ(report.repaired_segments, 0);
  ASSERT_EQ(path.size(), 2u);
  EXPECT_EQ(path[1].t, out.t);
  EXPECT_EQ(f.checker.checks(), before);
}

TEST(Smoother, WithWaypointAtInsertsAPoseInsideASegmentOnly) {
  // Three waypoints 10 apart along x, no turning: with the metric's nu = 1
  // and u = 1/2 each segment has length 5, the path up to waypoint 2 has 10.
  PlanningProblem problem;
  problem.metric.nu = 1.0;
  std::vector<Pose> path(3);
  for (int i = 0; i < 3; ++i) path[i].t = {10.0 * i, 0, 0};
  std::size_t index = 99;
  std::vector<Pose> out = WithWaypointAt(problem, path, 2, 0.25, &index);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(index, 1u);
  EXPECT_NEAR(out[1].t.x(), 5.0, 1e-12);
  EXPECT_EQ(out[2].t.x(), 10.0);
  out = WithWaypointAt(problem, path, 2, 0.5, &index);  // on waypoint 1: nothing inserted
  EXPECT_EQ(out.size(), 3u);
  EXPECT_EQ(index, 1u);
  out = WithWaypointAt(problem, path, 2, 0.0, &index);
  EXPECT_EQ(out.size(), 3u);
  EXPECT_EQ(index, 0u);
  out = WithWaypointAt(problem, path, 2, 1.0, &index);
  EXPECT_EQ(out.size(), 3u);
  EXPECT_EQ(index, 2u);
  out = WithWaypointAt(problem, path, 1, 0.5, &index);  // half of the part up to waypoint 1
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(index, 1u);
  EXPECT_NEAR(out[1].t.x(), 5.0, 1e-12);
}

TEST(Smoother, FirstFreezeThatWorksRefinesBetweenTheLastFailureAndTheFirstSuccess) {
  // Works from 0.3 on: the coarse step finds 5/16 = 0.3125, the finer ones
  // between 4/16 and 5/16 (eighths of 1/16) then 0.3046875, the first >= 0.3.
  std::vector<double> tried;
  double kept = -1;
  const bool found = FirstFreezeThatWorks([&](double fraction) {
    tried.push_back(fraction);
    if (fraction < 0.3) return false;
    kept = fraction;
    return true;
  });
  EXPECT_TRUE(found);
  EXPECT_DOUBLE_EQ(kept, (4 + 7.0 / 8) / 16);
  ASSERT_EQ(tried.size(), 6u + 7u);
  EXPECT_DOUBLE_EQ(tried[5], 5.0 / 16);
  EXPECT_FALSE(FirstFreezeThatWorks([](double) { return false; }));
}

TEST(StateSpace, GuidedSamplesLieNearTheCourseHalfOfTheTime) {
  Fixture f("two-boxes");
  PlanningProblem problem = f.problem;
  problem.fixed_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d a = problem.bounds.min + 0.25 * problem.bounds.Size();
  const Eigen::Vector3d b = problem.bounds.min + 0.3 * problem.bounds.Size();
  Pose pa, pb;
  pa.t = a;
  pb.t = b;
  problem.sampling_guide = {pa, pb};
  Random random(7);
  int near = 0;
  constexpr int kSamples = 4000;
  for (int i = 0; i < kSamples; ++i) {
    const Pose pose = problem.SampleUniform(random);
    EXPECT_EQ(pose.q.coeffs(), problem.fixed_rotation->coeffs());
    // Distance from the segment a-b.
    const double s = std::clamp((pose.t - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    if ((pose.t - (a + s * (b - a))).norm() <= problem.robot_diagonal * (1 + 1e-9)) ++near;
  }
  // Half drawn near the course (all within D's diagonal of it), the other
  // half uniform in the bounds (few of them that near).
  EXPECT_GT(near, kSamples * 45 / 100);
  EXPECT_LT(near, kSamples * 70 / 100);
}

// The FCL checker without its proof of whole motions (ProvesMotions false).
class CheckerWithoutSweeps : public PoseValidity {
 public:
  explicit CheckerWithoutSweeps(const FclCollisionChecker& fcl) : fcl_(fcl) {}

 protected:
  bool CheckValid(const Pose& pose) const override { return !fcl_.InCollision(pose); }

 private:
  const FclCollisionChecker& fcl_;
};

// Walks `trials` random motions from valid poses with and without sweeps;
// returns how many were blocked and how many were valid as a whole.
std::pair<int, int> CompareSweepingAndWalking(const PlanningProblem& problem, const FclCollisionChecker& checker,
                                              const CheckerWithoutSweeps& plain, int trials) {
  const double step = 0.01 * problem.robot_diagonal;
  const MotionChecker sweeping(problem, checker, step), walking(problem, plain, step);
  Random random(9);
  int blocked = 0, whole = 0;
  for (int trial = 0; trial < trials; ++trial) {
    Pose a = problem.SampleUniform(random);
    while (!walking.IsValid(a)) a = problem.SampleUniform(random);
    const Pose b = problem.SampleUniform(random);
    Pose reached_sweeping, reached_walking;
    const double fraction = sweeping.ValidPrefix(a, b, &reached_sweeping);
    EXPECT_EQ(fraction, walking.ValidPrefix(a, b, &reached_walking)) << "trial " << trial;
    EXPECT_TRUE(reached_sweeping.t == reached_walking.t && reached_sweeping.q.coeffs() == reached_walking.q.coeffs());
    const bool valid = sweeping.MotionValid(a, b);
    EXPECT_EQ(valid, walking.MotionValid(a, b)) << "trial " << trial;
    blocked += fraction < 1;
    whole += valid;
  }
  return {blocked, whole};
}

TEST(MotionChecker, SweepsChangeTheChecksNotTheAnswers) {
  Fixture f("peg-in-plate");
  const CheckerWithoutSweeps plain(f.checker);
  ASSERT_TRUE(f.checker.ProvesMotions());
  ASSERT_FALSE(plain.ProvesMotions());
  const auto [blocked, whole] = CompareSweepingAndWalking(f.problem, f.checker, plain, 300);
  EXPECT_GT(blocked, 30);  // both kinds of motion are exercised
  EXPECT_GT(whole, 30);
  // Much of the box around the plate is open space, where a sweep proves
  // what would take dozens of checks.
  EXPECT_LT(f.checker.checks(), plain.checks() / 2);
}

// At the certification's step, short motions close to S: proofs by D's
// clearance at their middle change the checks, not the answers.
TEST(MotionChecker, ProofsByClearanceChangeTheChecksNotTheAnswers) {
  Fixture f("peg-in-plate");
  const CheckerWithoutSweeps plain(f.checker);
  const FclCollisionChecker sweeps_only(f.problem.robot, f.problem.environment);
  ASSERT_TRUE(f.checker.ProvesMotionsByClearance());
  const double step = kCertificationResolution * f.problem.robot_diagonal;
  MotionChecker by_clearance(f.problem, f.checker, step);
  by_clearance.ProveByClearance();
  const MotionChecker sweeping(f.problem, sweeps_only, step), walking(f.problem, plain, step);
  Random random(11);
  int valid = 0, blocked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Pose a = f.problem.SampleUniform(random);
    while (!walking.IsValid(a)) a = f.problem.SampleUniform(random);
    // A motion of up to 0.4 of D's diagonal and 0.2 rad from a.
    Pose b = a;
    b.t += 0.4 * f.problem.robot_diagonal *
           Eigen::Vector3d(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)) / std::sqrt(3.0);
    b.q =
        (a.q * Eigen::Quaterniond(Eigen::AngleAxisd(random.Uniform(-0.2, 0.2), Eigen::Vector3d::UnitX()))).normalized();
    const bool answer = walking.MotionValid(a, b);
    EXPECT_EQ(answer, by_clearance.MotionValid(a, b)) << "trial " << trial;
    EXPECT_EQ(answer, sweeping.MotionValid(a, b)) << "trial " << trial;
    valid += answer;
    blocked += !answer;
  }
  EXPECT_GT(valid, 30);  // both kinds of motion are exercised
  EXPECT_GT(blocked, 30);
  EXPECT_LT(f.checker.checks(), sweeps_only.checks());
}

TEST(MotionChecker, SweepsKeepATurningBoundedPointInBounds) {
  // The bounds hold a point two diagonals off D's reference point (as where
  // a scene's mesh origin lies far from its part): while D turns, that point
  // swings out of the bounds between two poses inside them, which a sweep
  // of the validity does not see; the walk pose by pose does.
  Fixture f("peg-in-plate");
  PlanningProblem problem = f.problem;
  problem.bounded_point = Eigen::Vector3d(2 * problem.robot_diagonal, 0, 0);
  const CheckerWithoutSweeps plain(f.checker);
  const auto [blocked, whole] = CompareSweepingAndWalking(problem, f.checker, plain, 300);
  EXPECT_GT(blocked, 30);
  EXPECT_GT(whole, 10);
}

TEST(Planner, SamplersWorkInsideTheTreePlanners) {
  Fixture f("peg-in-plate");
  for (const char* sampler : {"gaussian", "bridge", "mixed"}) {
    PlannerOptions options;
    options.sampler = sampler;
    options.seed = 2;
    options.time_limit_s = 120;
    const PlanResult result = Plan(f.problem, f.checker, options);
    ASSERT_TRUE(result.solved()) << sampler;
    EXPECT_GT(result.stats.invalid_checks, 0);
    EXPECT_LT(result.stats.invalid_checks, result.stats.collision_checks);
    ExpectValidPath(f, result.path);
  }
}

TEST(Prm, AnswersSeveralQueriesFromOneRoadmap) {
  Fixture f("two-boxes");
  const MotionChecker motion(f.problem, f.checker, 0.005 * f.problem.robot_diagonal);
  auto at = [](double x, double y, double z, double angle) {
    Pose p;
    p.t = {x, y, z};
    p.q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()));
    return p;
  };
  const std::vector<PrmQuery> queries = {
      {f.problem.start, f.problem.goal},
      {at(0, 3, 0, 0.3), at(0, -3, 0, 1.0)},
      {at(0, 0, 3, 0.0), at(0, 0, -3, 2.0)},
      {at(3, 3, 3, 0.0), std::nullopt},  // disassembly: already out, or nearby
  };
  PlannerOptions options;
  options.seed = 4;
  options.time_limit_s = 120;
  for (int threads : {1, 2}) {
    PrmSettings settings;
    settings.threads = threads;
    const PrmResult result = RunPrm(f.problem, motion, queries, settings, options);
    ASSERT_EQ(result.queries.size(), queries.size());
    EXPECT_GT(result.edges, 0);
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const PlanResult& answer = result.queries[q];
      ASSERT_TRUE(answer.solved()) << "query " << q << " threads " << threads;
      EXPECT_TRUE(answer.path.front().t.isApprox(queries[q].start.t));
      if (queries[q].goal) {
        EXPECT_TRUE(answer.path.back().t.isApprox(queries[q].goal->t));
      } else {
        EXPECT_TRUE(f.problem.InGoalRegion(answer.path.back()));
      }
      const DenseCheckReport report =
          DenseCheckPath(f.scene, f.problem.reference_point, f.ToScene(answer.path), kDenseStep);
      EXPECT_TRUE(report.valid) << "query " << q << ": " << report.reason;
    }
  }
}

TEST(Sampler, GaussianSamplesLieNearerToObstaclesThanUniformOnes) {
  Fixture f("peg-in-plate");
  const MotionChecker motion(f.problem, f.checker, 0.005 * f.problem.robot_diagonal);
  Random random(8);
  // Mean clearance of valid samples; fallbacks (a bridge or Gaussian
  // sampler that found nothing within its tries returns a uniform pose) are
  // left out, so that the statistic is about the strategy itself.
  auto mean_distance = [&](SamplerKind kind, int min_count) {
    Sampler sampler(f.problem, motion, kind, 0.0);
    double sum = 0;
    int count = 0;
    for (int i = 0; i < 400; ++i) {
      Pose pose;
      const std::int64_t fallbacks = sampler.fallbacks();
      if (!sampler.SampleValid(random, &pose, 100) || sampler.fallbacks() != fallbacks) continue;
      EXPECT_TRUE(motion.IsValid(pose));
      sum += f.checker.Distance(pose);
      ++count;
    }
    EXPECT_GE(count, min_count);
    return sum / count;
  };
  const double uniform = mean_distance(SamplerKind::kUniform, 300);
  const double gaussian = mean_distance(SamplerKind::kGaussian, 300);
  const double bridge = mean_distance(SamplerKind::kBridge, 10);
  EXPECT_LT(gaussian, 0.5 * uniform);
  EXPECT_LT(bridge, 0.5 * uniform);
  EXPECT_THROW(ParseSamplerKind("nope"), InputError);
}

// The library names the field, not a flag its caller may not have; the
// error carries the field's address for the stage runner to name the flag.
TEST(OptionCheck, NamesTheFieldAndWhereItLives) {
  PlannerOptions planner;
  planner.range_max = 0;
  try {
    planner.Check();
    FAIL() << "range_max 0 was accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), &planner.range_max);
    EXPECT_EQ(std::string(e.what()), "range_max: must lie in (0, 1]");
  }
  planner = PlannerOptions();
  planner.sampler = "nope";
  try {
    planner.Check();
    FAIL() << "sampler 'nope' was accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), &planner.sampler);
    EXPECT_EQ(e.field_name(), "sampler");
  }
}

TEST(DenseCheck, FindsACollisionBetweenValidWaypoints) {
  // Two collision-free poses on either side of the static box: the straight
  // motion between them passes through it.
  Fixture f("two-boxes");
  Pose a = f.scene.start, b = f.scene.start;
  b.t.x() = 3.0;
  const DenseCheckReport report = DenseCheckPath(f.scene, f.problem.reference_point, {a, b}, 0.01);
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.first_bad_segment, 0);
  EXPECT_EQ(report.reason, "in collision");
}

}  // namespace
}  // namespace ausbau
