// CR-RRTC on the public OMPL.app scenes (../shared/benchmarks/ompl): each
// solves within an iteration budget (deterministic, unlike a time limit) and
// its path, raw and smoothed, passes the dense re-check at 1% of D's
// diagonal. Skipped when the benchmark folder is absent.
#include <gtest/gtest.h>

#include "collision/fcl_checker.h"
#include "planning/dense_check.h"
#include "planning/planner.h"
#include "planning/smoother.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

class OmplScene : public ::testing::TestWithParam<const char*> {};

TEST_P(OmplScene, CrRrtcSolvesAndPathsPassTheDenseCheck) {
  const auto yaml = testing::OmplScene(GetParam());
  if (yaml.empty()) GTEST_SKIP() << "../shared/benchmarks/ompl/" << GetParam() << ".yaml not found";
  const Scene scene = LoadScene(yaml);
  const PlanningProblem problem = MakePlanningProblem(scene);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  CheckEndpoints(problem, checker, yaml.string());
  for (std::uint64_t seed : {1, 2}) {
    PlannerOptions options;
    options.seed = seed;
    options.time_limit_s = 1e6;       // the iteration budget decides
    options.max_iterations = 200000;  // far above what the runs need (see README)
    const PlanResult result = Plan(problem, checker, options);
    ASSERT_TRUE(result.solved()) << GetParam() << " seed " << seed;
    SmoothOptions smooth;
    smooth.seed = seed;
    smooth.time_limit_s = 1e6;
    const SmoothResult smoothed = SmoothPath(problem, checker, result.path, smooth);
    for (const auto* path : {&result.path, &smoothed.path}) {
      std::vector<Pose> scene_path;
      for (const Pose& p : *path) scene_path.push_back(problem.PlanningToScene(p));
      EXPECT_TRUE(scene_path.front().t.isApprox(scene.start.t, 1e-9));
      EXPECT_TRUE(scene_path.back().t.isApprox(scene.goal->t, 1e-9));
      const DenseCheckReport report = DenseCheckPath(scene, problem.reference_point, scene_path, 0.01);
      EXPECT_TRUE(report.valid) << GetParam() << " seed " << seed << ": segment " << report.first_bad_segment << " "
                                << report.reason;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Benchmarks, OmplScene, ::testing::Values("Easy", "alpha-1.5", "Apartment"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace ausbau
