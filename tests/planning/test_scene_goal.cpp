// Goals that fit the job (schemas/scene.md "Goals", planning/scene_goal.h):
// goal: {clearance}, goal: {region} in scene.yaml, the test every consumer
// shares (planner goal test, exact check, verdict), on a box D beside a box
// S whose distances are known by hand; and one run of ausbau-plan and
// ausbau-verdict on a scene with a clearance goal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "collision/fcl_checker.h"
#include "core/error.h"
#include "geometry/primitives.h"
#include "planning/exact_check.h"
#include "planning/path_io.h"
#include "planning/scene_goal.h"
#include "planning/state_space.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// S: the surface of the cube [0, 10]^3. D: the cube [0, 2]^3 with
// dynamic_origin at its centre (1, 1, 1), so that a pose's t is D's centre.
// At t = (13, 5, 5) D spans x in [12, 14]: 2 from S's face x = 10.
fs::path WriteScene(const std::string& goal) {
  const fs::path dir = testing::MakeTempDir("scene-goal");
  SaveObj(MakeBox(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 10, 10)), dir / "s.obj");
  SaveObj(MakeBox(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 2, 2)), dir / "d.obj");
  std::ofstream(dir / "scene.yaml") << "format: ausbau-scene/1\nunits: mm\nstatic: [s.obj]\ndynamic: d.obj\n"
                                    << "dynamic_origin: [1, 1, 1]\nstart: {t: [13, 5, 5]}\n"
                                    << goal;
  return dir / "scene.yaml";
}

Pose At(double x, double y = 5, double z = 5) {
  Pose pose;
  pose.t = {x, y, z};
  return pose;
}

std::string LoadError(const std::string& goal) {
  try {
    LoadScene(WriteScene(goal));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneGoal, ParsesTheConditionFormsAndKeepsThePose) {
  const Scene clearance = LoadScene(WriteScene("goal: {clearance: 50}\n"));
  EXPECT_FALSE(clearance.goal.has_value());
  ASSERT_TRUE(clearance.goal_condition.has_value());
  EXPECT_EQ(clearance.goal_condition->clearance, 50);
  EXPECT_FALSE(clearance.goal_condition->region.has_value());

  const Scene both = LoadScene(WriteScene("goal: {clearance: 2.5, region: {min: [11, 0, 0], max: [30, 10, 10]}}\n"));
  ASSERT_TRUE(both.goal_condition && both.goal_condition->region);
  EXPECT_EQ(both.goal_condition->region->min, Eigen::Vector3d(11, 0, 0));
  EXPECT_EQ(both.goal_condition->clearance, 2.5);

  const Scene pose = LoadScene(WriteScene("goal: {t: [20, 5, 5], q: [1, 0, 0, 0]}\n"));
  EXPECT_TRUE(pose.goal.has_value());
  EXPECT_FALSE(pose.goal_condition.has_value());

  // The writer writes it back as it was read.
  const fs::path copy = both.file.parent_path() / "copy.yaml";
  SaveSceneYaml(both, copy);
  const Scene again = LoadScene(copy);
  ASSERT_TRUE(again.goal_condition && again.goal_condition->region);
  EXPECT_EQ(again.goal_condition->clearance, 2.5);
  EXPECT_EQ(again.goal_condition->region->max, Eigen::Vector3d(30, 10, 10));
}

TEST(SceneGoal, BadGoalsNameTheKey) {
  EXPECT_NE(LoadError("goal: {clearance: -1}\n").find("goal.clearance must be a number > 0"), std::string::npos);
  EXPECT_NE(LoadError("goal: {clearance: abc}\n").find("goal.clearance"), std::string::npos);
  EXPECT_NE(LoadError("goal: {clearance: 5, t: [1, 2, 3]}\n").find("either a pose {t, q} or a condition"),
            std::string::npos);
  EXPECT_NE(LoadError("goal: {region: {min: [0, 0, 0]}}\n").find("missing required key 'goal.region.max'"),
            std::string::npos);
  EXPECT_NE(LoadError("goal: {region: {min: [0, 0, 0], max: [1, 0, 1]}}\n").find("goal.region.min >= goal.region.max"),
            std::string::npos);
  EXPECT_NE(LoadError("goal: {region: {min: [0, 0, 0], max: [1, 1, 1]}, clearence: 3}\n").find("'goal.clearence'"),
            std::string::npos);
}

TEST(SceneGoal, ClearanceIsTheExactDistance) {
  const SceneGoal goal(LoadScene(WriteScene("goal: {clearance: 5}\n")));
  EXPECT_FALSE(goal.Check(At(13)).met);  // 2 from S
  EXPECT_NE(goal.Check(At(13)).why_not.find("D is 2 from S, less than the goal's clearance 5"), std::string::npos)
      << goal.Check(At(13)).why_not;
  EXPECT_FALSE(goal.Check(At(15.99)).met);  // 4.99
  EXPECT_TRUE(goal.Check(At(16.01)).met);   // 5.01
  // Diagonally off S's corner (10, 10, 10): D's nearest corner (14, 14, 14) lies sqrt(3) * 4 = 6.93 away.
  EXPECT_TRUE(goal.Check(At(15, 15, 15)).met);
  // The AABB separation alone (the default) is met at 2 already.
  EXPECT_TRUE(SceneGoal(LoadScene(WriteScene(""))).Check(At(13)).met);
  EXPECT_FALSE(SceneGoal(LoadScene(WriteScene(""))).Check(At(10.5)).met);
}

TEST(SceneGoal, RegionHoldsTheReferencePointAndDMustNotTouchS) {
  const SceneGoal goal(LoadScene(WriteScene("goal: {region: {min: [4, 4, 4], max: [12, 6, 6]}}\n")));
  EXPECT_TRUE(goal.Check(At(5)).met);      // D in S's cavity, x in [4, 6], touching nothing
  EXPECT_FALSE(goal.Check(At(10.5)).met);  // t inside, but D (x in [9.5, 11.5]) crosses S's face
  EXPECT_FALSE(goal.Check(At(13)).met);    // t outside the region
  EXPECT_NE(goal.Check(At(13)).why_not.find("outside the goal region"), std::string::npos);
  // The AABB separation is not asked for: the default goal refuses D in the cavity.
  EXPECT_FALSE(SceneGoal(LoadScene(WriteScene(""))).Check(At(5)).met);
}

TEST(SceneGoal, TheGoalPoseIsTheEnd) {
  const SceneGoal goal(LoadScene(WriteScene("goal: {t: [20, 5, 5]}\n")));
  EXPECT_TRUE(goal.Check(At(20)).met);
  EXPECT_FALSE(goal.Check(At(20.01)).met);
  EXPECT_FALSE(goal.Check(At(30)).met);  // farther out is not the goal
}

TEST(SceneGoal, ThePlannersGoalTestAndSamplerUseIt) {
  const Scene scene = LoadScene(WriteScene("goal: {clearance: 5, region: {min: [15, 0, 0], max: [25, 10, 10]}}\n"));
  const PlanningProblem problem = MakePlanningProblem(scene);
  ASSERT_TRUE(problem.goal_test);
  EXPECT_FALSE(problem.goal.has_value());
  EXPECT_FALSE(problem.InGoalRegion(problem.SceneToPlanning(At(13))));
  EXPECT_FALSE(problem.InGoalRegion(problem.SceneToPlanning(At(15.5))));  // in the region, 4.5 from S
  EXPECT_TRUE(problem.InGoalRegion(problem.SceneToPlanning(At(16.5))));
  EXPECT_FALSE(problem.InGoalRegion(problem.SceneToPlanning(At(26))));  // 15 from S, outside the region
  // Derived bounds leave room for the clearance: S's box and the start, grown by 1.5 D diagonals + 5.
  EXPECT_NEAR(problem.bounds.max.x(), 13 + 1.5 * std::sqrt(12.0) + 5, 1e-9);
  Random random(7);
  for (int i = 0; i < 20; ++i) {
    Pose pose;
    ASSERT_TRUE(SampleGoalRegion(problem, random, &pose));
    const Pose scene_pose = problem.PlanningToScene(pose);
    EXPECT_TRUE(scene.goal_condition->region->Contains(scene_pose.t));
    EXPECT_TRUE(SceneGoal(scene).Check(scene_pose).met);
  }
  // A region outside given bounds is bad input.
  EXPECT_THROW(MakePlanningProblem(LoadScene(
                   WriteScene("bounds: {min: [-5, -5, -5], max: [15, 15, 15]}\ngoal: {region: {min: [20, 0, 0], "
                              "max: [25, 10, 10]}}\n"))),
               InputError);
}

TEST(SceneGoal, TheExactCheckJudgesTheEndByTheGoal) {
  const Scene scene = LoadScene(WriteScene("goal: {clearance: 4}\n"));
  const std::vector<Pose> out_by_5 = {At(13), At(18)};  // ends 7 from S
  const std::vector<Pose> out_by_1 = {At(13), At(14)};  // ends 3 from S: AABB-separated, short of the clearance
  EXPECT_TRUE(ExactCheckPath(scene, out_by_5, 0.05).valid);
  const ExactCheckReport short_end = ExactCheckPath(scene, out_by_1, 0.05);
  EXPECT_FALSE(short_end.valid);
  EXPECT_FALSE(short_end.ends_in_goal);
  EXPECT_TRUE(short_end.ends_separated);
  EXPECT_NE(short_end.reason.find("misses the goal (D at least 4 from S)"), std::string::npos) << short_end.reason;
}

// ausbau-plan and ausbau-verdict on a scene with a clearance goal: the path
// ends at least the clearance from S, and the verdict accepts it; the same
// path judged against a larger clearance is refused.
TEST(SceneGoalStages, PlanAndVerdictMeetAClearanceGoal) {
  const fs::path yaml = WriteScene("goal: {clearance: 20}\n");
  const fs::path dir = yaml.parent_path();
  const std::string scene = " --scene " + yaml.string();
  auto run = testing::RunStageCommand(
      "plan", scene + " --seed 3 -o " + (dir / "path.h5").string() + " --csv " + (dir / "path.csv").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<Pose> path = ReadPathCsv(dir / "path.csv");
  const Scene loaded = LoadScene(yaml);
  FclCollisionChecker fcl(
      [&] {
        TriangleMesh d = loaded.dynamic_mesh;
        for (auto& v : d.vertices) v -= loaded.dynamic_origin;
        return d;
      }(),
      loaded.static_mesh);
  EXPECT_GE(fcl.Distance(path.back()), 20.0);
  const std::string judge = scene + " --path " + (dir / "path.h5").string() + " --csv-name " +
                            (dir / "path.csv").string() + " -o " + (dir / "verdict.json").string();
  run = testing::RunStageCommand("verdict", judge);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("REMOVABLE"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("NOT REMOVABLE"), std::string::npos) << run.output;

  // The same path against a goal it does not reach: never removable.
  std::ofstream(yaml, std::ios::trunc) << "format: ausbau-scene/1\nunits: mm\nstatic: [s.obj]\ndynamic: d.obj\n"
                                       << "dynamic_origin: [1, 1, 1]\nstart: {t: [13, 5, 5]}\n"
                                       << "goal: {clearance: " << fcl.Distance(path.back()) + 1 << "}\n";
  run = testing::RunStageCommand("verdict", judge);
  EXPECT_NE(run.output.find("NOT REMOVABLE"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("misses the goal"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace ausbau
