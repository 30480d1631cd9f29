// workflow/verdict.h: JudgeRun in process on a scene small enough to check
// by hand. D, a unit cube (z from 0.5 to 1.5), stands between two walls
// (x in [-2, -1] and [1, 2], y in [-1, 1], z in [0, 2]), 0.5 from each;
// every length in mm. The default goal is D's box clear of S's box
// (x in [-2, 2], y in [-1, 1], z in [0, 2]).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "planning/path_io.h"
#include "scene/scene.h"
#include "test_cube_between_walls.h"
#include "test_poses.h"
#include "test_scenes.h"
#include "workflow/verdict.h"

namespace ausbau {
namespace {

using testing::PoseAt;
using testing::WriteCubeBetweenWalls;

class JudgeRunTest : public ::testing::Test {
 protected:
  void SetUp() override { scene_ = WriteCubeBetweenWalls(dir_.path()); }

  // Writes a path artifact (as ausbau-plan would, without recorded inputs:
  // nothing for the verdict's made-from check to compare) and judges it.
  Verdict Judge(const std::vector<Pose>& waypoints, bool success = true, const std::vector<Pose>& partial = {},
                bool stopped_by_budget = false) {
    PathArtifact path;
    path.waypoints = waypoints;
    path.success = success;
    path.partial_waypoints = partial;
    path.stopped_by_budget = stopped_by_budget;
    path.planner = "by hand";
    path.units = "mm";
    const std::string file = (dir_ / "path.h5").string();
    WritePathArtifact(file, path, Provenance{"ausbau-plan", AUSBAU_VERSION, "", {}});
    VerdictInputs inputs;
    inputs.path = file;
    return JudgeRun(scene_, inputs);
  }

  testing::ScopedTempDir dir_{"judge_run"};
  Scene scene_;
};

TEST_F(JudgeRunTest, StraightUpIsRemovable) {
  // Up by 3: D's box ends at z in [3.5, 4.5], above S's (z <= 2), and never
  // comes nearer a wall than 0.5.
  const Verdict v = Judge({PoseAt(0, 0, 0), PoseAt(0, 0, 3)});
  EXPECT_TRUE(v.removable);
  EXPECT_EQ(VerdictStatusDetail(v), "removable");
  EXPECT_DOUBLE_EQ(v.tolerance, 0.05);  // the default 0.05 mm, the scene in mm
  ASSERT_TRUE(v.exact.has_value());
  EXPECT_TRUE(v.exact->valid) << v.exact->reason;
  EXPECT_TRUE(v.exact->starts_at_start);
  EXPECT_TRUE(v.exact->ends_in_goal);
  EXPECT_EQ(v.exact->max_rigid_depth, 0);
  EXPECT_FALSE(v.blocking.has_value());  // only asked where D is not removable
  ASSERT_TRUE(v.quality.has_value());
}

TEST_F(JudgeRunTest, ThroughAWallIsNotRemovable) {
  // Sideways by 5: the end is clear of S (x in [4.5, 5.5]), but on the way D
  // passes through the right wall, 1 thick: far deeper than 0.05.
  const Verdict v = Judge({PoseAt(0, 0, 0), PoseAt(5, 0, 0)});
  EXPECT_FALSE(v.removable);
  EXPECT_EQ(VerdictStatusDetail(v), "not-removable (exact check failed)");
  ASSERT_TRUE(v.exact.has_value());
  EXPECT_FALSE(v.exact->valid);
  EXPECT_TRUE(v.exact->starts_at_start);
  EXPECT_EQ(v.exact->first_bad_segment, 0);
  EXPECT_GT(v.exact->max_rigid_depth, 0.05);
  EXPECT_TRUE(v.blocking.has_value());  // what holds D: the straight pulls
}

TEST_F(JudgeRunTest, StoppingShortOfTheGoalIsNotRemovable) {
  // Up by 1 only: D's box (z in [1.5, 2.5]) still overlaps S's box.
  const Verdict v = Judge({PoseAt(0, 0, 0), PoseAt(0, 0, 1)});
  EXPECT_FALSE(v.removable);
  ASSERT_TRUE(v.exact.has_value());
  EXPECT_TRUE(v.exact->starts_at_start);
  EXPECT_FALSE(v.exact->ends_in_goal);
  EXPECT_EQ(v.exact->max_rigid_depth, 0);
}

TEST_F(JudgeRunTest, NotStartingAtTheInstalledPoseIsNotRemovable) {
  // The same motion up, from 0.2 beside the installed pose.
  const Verdict v = Judge({PoseAt(0.2, 0, 0), PoseAt(0.2, 0, 3)});
  EXPECT_FALSE(v.removable);
  ASSERT_TRUE(v.exact.has_value());
  EXPECT_FALSE(v.exact->starts_at_start);
}

TEST_F(JudgeRunTest, NoPathIsNotRemovableWithoutAnExactCheck) {
  const Verdict v = Judge({}, /*success=*/false);
  EXPECT_FALSE(v.removable);
  EXPECT_EQ(VerdictStatusDetail(v), "not-removable (no path)");
  EXPECT_FALSE(v.exact.has_value());
  EXPECT_FALSE(v.blocked_at_partial_end);  // no partial path: blocked where installed
  EXPECT_TRUE(v.blocked_at.t.isZero());
}

TEST_F(JudgeRunTest, WhatBlocksIsAskedAtTheEndOfAPartialPathThatCountedWorkEnded) {
  // The search ended by its iterations (--max-iterations) with D raised by
  // 0.2: the same end on any machine, so what blocks D is asked there.
  const Verdict v = Judge({}, /*success=*/false, {PoseAt(0, 0, 0), PoseAt(0, 0, 0.2)});
  EXPECT_EQ(VerdictStatusDetail(v), "not-removable (no path)");
  EXPECT_TRUE(v.blocked_at_partial_end);
  EXPECT_DOUBLE_EQ(v.blocked_at.t.z(), 0.2);
}

TEST_F(JudgeRunTest, WhatBlocksIsAskedAtTheInstalledPoseWhereTheClockEndedTheSearch) {
  // The same partial path, but the time limit ended the search: how far it
  // got depends on the machine and its load, so what blocks D is asked at
  // the installed pose, and the partial path is only reported.
  const Verdict v = Judge({}, /*success=*/false, {PoseAt(0, 0, 0), PoseAt(0, 0, 0.2)}, /*stopped_by_budget=*/true);
  EXPECT_EQ(VerdictStatusDetail(v), "not-removable (budget)");
  EXPECT_FALSE(v.blocked_at_partial_end);
  EXPECT_TRUE(v.blocked_at.t.isZero());
  EXPECT_EQ(v.path.partial_waypoints.size(), 2u);
}

}  // namespace
}  // namespace ausbau
