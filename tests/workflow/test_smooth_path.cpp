// workflow/smooth_path.h: SmoothPlannedPath in process on a path with a
// needless detour, in a scene small enough to check by hand. D, a unit cube
// (z from 0.5 to 1.5), stands between two walls (x in [-2, -1] and [1, 2],
// y in [-1, 1], z in [0, 2]); above z = 2 there is nothing. The planned
// path goes up out of the walls, then 3 aside, 3 up and 3 back: 12 mm where
// straight up to its end is 6, and 1.5 up is enough to clear S's box.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "planning/dense_check.h"
#include "planning/path_io.h"
#include "planning/state_space.h"
#include "scene/scene.h"
#include "test_cube_between_walls.h"
#include "test_poses.h"
#include "test_scenes.h"
#include "workflow/smooth_path.h"

namespace ausbau {
namespace {

using testing::PoseAt;
using testing::WriteCubeBetweenWalls;

class SmoothPlannedPathTest : public ::testing::Test {
 protected:
  void SetUp() override { scene_ = WriteCubeBetweenWalls(dir_.path()); }

  // The planned path as ausbau-plan writes it (plain collision), about the
  // reference point of the problem that holds it.
  PathArtifact Planned(const std::vector<Pose>& waypoints, const PlanningProblem& problem) {
    PathArtifact path;
    path.waypoints = waypoints;
    path.success = true;
    path.planner = "by hand";
    path.units = "mm";
    path.reference_point = problem.reference_point;
    path.dynamic_origin = scene_.dynamic_origin;
    WritePathArtifact(file_, path, Provenance{"ausbau-plan", AUSBAU_VERSION, "", {}});
    return ReadPathArtifact(file_);
  }

  testing::ScopedTempDir dir_{"smooth_planned_path"};
  std::string file_ = (dir_ / "path.h5").string();
  Scene scene_;
};

TEST_F(SmoothPlannedPathTest, TheDetourGoesAndThePathStaysValid) {
  const std::vector<Pose> detour = {PoseAt(0, 0, 0), PoseAt(0, 0, 3), PoseAt(0, 3, 3), PoseAt(0, 3, 6),
                                    PoseAt(0, 0, 6)};
  const PlanningProblem problem = MakePlanningProblemHolding(scene_, detour);
  const PathArtifact input = Planned(detour, problem);
  ASSERT_TRUE(DenseCheckPath(scene_, input.reference_point, input.waypoints, 0.01).valid);

  const SmoothedPath smoothed = SmoothPlannedPath(scene_, problem, input, file_, SmoothPlannedPathOptions());
  const std::vector<Pose>& out = smoothed.artifact.waypoints;
  ASSERT_GE(out.size(), 2u);
  // The input's translation as measured: 3 + 3 + 3 + 3.
  EXPECT_NEAR(smoothed.result.before.translation, 12, 1e-9);
  // Shorter: without the 3 aside and back at least, so at most the 6 of
  // straight up; and no shorter than D must move to clear S's box (1.5).
  EXPECT_LE(smoothed.result.after.translation, 6 + 1e-9);
  EXPECT_GE(smoothed.result.after.translation, 1.5);
  // In fact the shortest way out: straight up (or along y, between the
  // walls) by the 1.5 that clears S's box, plus the smoother's margin of 1%
  // of D's diagonal (sqrt(3)): planning/smoother.h, StraightExitPose.
  EXPECT_NEAR(smoothed.result.after.translation, 1.5 + 0.01 * std::sqrt(3.0), 1e-6);
  EXPECT_DOUBLE_EQ(smoothed.artifact.length_translation, smoothed.result.after.translation);
  // Still from the installed pose, out of S's box, and valid under the
  // independent dense check.
  EXPECT_TRUE(out.front().t.isApprox(scene_.start.t, 1e-12)) << out.front().t.transpose();
  EXPECT_TRUE(problem.InGoalRegion(problem.SceneToPlanning(out.back())));
  const DenseCheckReport check = DenseCheckPath(scene_, problem.reference_point, out, 0.01);
  EXPECT_TRUE(check.valid) << "segment " << check.first_bad_segment << ": " << check.reason;
  EXPECT_GT(smoothed.result.shortcuts, 0);
}

TEST_F(SmoothPlannedPathTest, AnInputThroughAWallIsRefused) {
  // Sideways through the right wall: the smoother refuses to start from it.
  const std::vector<Pose> through = {PoseAt(0, 0, 0), PoseAt(5, 0, 0)};
  const PlanningProblem problem = MakePlanningProblemHolding(scene_, through);
  const PathArtifact input = Planned(through, problem);
  EXPECT_THROW(SmoothPlannedPath(scene_, problem, input, file_, SmoothPlannedPathOptions()), InputError);
}

}  // namespace
}  // namespace ausbau
