// planning/exact_check.h: the exact check of a path as a file states it
// (plain interpolation, the installed pose, the goal), densifying for plain
// interpolation, and the straight pulls of what blocks D, on hand-checkable
// boxes. (Moved from the rigid-depth test: they need the planning layer.)
#include <gtest/gtest.h>

#include <cmath>

#include "collision/rigid_depth.h"
#include "collision/scene_parts.h"
#include "geometry/primitives.h"
#include "planning/exact_check.h"
#include "scene/scene.h"
#include "test_bar_in_channel.h"
#include "test_key_scene.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using testing::PoseAt;

using testing::KeyScene;  // a rigid key through a slot in a 2 mm plate (test_key_scene.h)

// The key scene as a scene (mm).
Scene KeyAsScene() {
  const KeyScene key;
  Scene scene;
  scene.dynamic_mesh = key.robot;
  scene.static_mesh = key.environment;
  scene.units = "mm";
  return scene;
}

TEST(ExactCheck, PlainInterpolationAndTheVerdictOfAPath) {
  const Scene scene = KeyAsScene();
  // Straight up and out: valid.
  std::vector<Pose> up = {Pose{}, PoseAt(0, 0, 40)};
  const ExactCheckReport ok = ExactCheckPath(scene, up, 0.05);
  EXPECT_TRUE(ok.valid) << ok.reason;
  EXPECT_TRUE(ok.ends_separated);
  EXPECT_LT(ok.max_rigid_depth, 0.05);
  // Sideways through the plate, then up: refused, with the depth and where.
  std::vector<Pose> cut = {Pose{}, PoseAt(40, 0, 0), PoseAt(40, 0, 40)};
  const ExactCheckReport bad = ExactCheckPath(scene, cut, 0.05);
  EXPECT_FALSE(bad.valid);
  EXPECT_GT(bad.max_rigid_depth, 1.0);
  EXPECT_EQ(bad.first_bad_segment, 0);
  EXPECT_EQ(bad.rigid_shell, 1);  // the key
  EXPECT_NE(bad.reason.find("penetrates"), std::string::npos);
  // Not ending separated.
  std::vector<Pose> short_path = {Pose{}, PoseAt(0, 0, 3)};
  EXPECT_FALSE(ExactCheckPath(scene, short_path, 0.05).valid);
}

// A caller that checks several paths of one scene (ausbau-smooth: its
// input and its output) passes the same ExactCheckModels: the scene is
// classified once, and every answer is the one without it.
TEST(ExactCheck, PathsOfOneSceneShareTheirClassification) {
  const Scene scene = KeyAsScene();
  ExactCheckModels models;
  const std::vector<Pose> up = {Pose{}, PoseAt(0, 0, 40)};
  const std::vector<Pose> cut = {Pose{}, PoseAt(40, 0, 0), PoseAt(40, 0, 40)};
  const ExactCheckReport first = ExactCheckPath(scene, up, 0.05, UnmeasuredInterference::kRigid, {}, &models);
  const ExactCheckReport second = ExactCheckPath(scene, cut, 0.05, UnmeasuredInterference::kRigid, {}, &models);
  ASSERT_EQ(models.by_level.size(), 1u);  // not cropped: the whole S
  EXPECT_EQ(first.parts, second.parts);   // the same classification, not a second one
  const ExactCheckReport alone = ExactCheckPath(scene, cut, 0.05);
  EXPECT_NE(alone.parts, second.parts);
  EXPECT_TRUE(first.valid);
  EXPECT_EQ(second.valid, alone.valid);
  EXPECT_EQ(second.reason, alone.reason);
  EXPECT_EQ(second.max_rigid_depth, alone.max_rigid_depth);
  EXPECT_EQ(second.first_bad_segment, alone.first_bad_segment);
}

TEST(ExactCheck, DensifyKeepsPlainInterpolationNearThePlannersOne) {
  // D metres from its mesh origin, turned 2 degrees about its own centre.
  const Eigen::Vector3d reference(3000, 0, 0), origin(0, 0, 0);
  Pose a, b;  // scene convention: x = R x + t, D's centre at 3000
  b.q = Eigen::Quaterniond(Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d::UnitY()));
  b.t = reference - b.q * reference;  // turn about D's centre
  const auto dense = DensifyForPlainInterpolation({a, b}, reference, origin, 0.005);
  ASSERT_GT(dense.size(), 2u);
  // Plain interpolation of each piece keeps D's centre within 0.005 of where it stays.
  for (std::size_t i = 0; i + 1 < dense.size(); ++i) {
    const Pose mid = Interpolate(dense[i], dense[i + 1], 0.5);
    EXPECT_LT((mid.Apply(reference) - reference).norm(), 0.005 + 1e-9);
  }
  // Without densifying, the centre dips ~0.46 mm mid-way.
  EXPECT_GT((Interpolate(a, b, 0.5).Apply(reference) - reference).norm(), 0.4);
  EXPECT_NEAR(RigidToleranceInSceneUnits(0.05, "m", nullptr), 5e-5, 1e-15);
  bool assumed = false;
  EXPECT_NEAR(RigidToleranceInSceneUnits(0.05, "", &assumed), 0.05, 1e-15);
  EXPECT_TRUE(assumed);
}

TEST(WhatBlocks, AClashAtTheInstalledPoseStopsEveryPullThereMeasuredOnce) {
  // A peg 2 x 1 x 10 whose side is 1 deep in a wall (far more than a fit of
  // a part this size): every pull is stopped where it starts, by the same
  // pose, which is measured once (1 depth measurement, the others none).
  Scene scene;
  scene.units = "mm";
  scene.dynamic_mesh = MakeBox({-1, -0.5, 0}, {1, 0.5, 10});
  scene.static_mesh = MakeBox({0, -5, -5}, {5, 5, 15});
  const double tolerance = 0.05;
  const BlockingReport report = ProbeWhatBlocks(scene, tolerance);
  ASSERT_FALSE(report.parts->rigid_interference.empty());
  ASSERT_EQ(report.probes.size(), 6u);
  for (std::size_t i = 0; i < report.probes.size(); ++i) {
    const BlockingProbe& p = report.probes[i];
    EXPECT_FALSE(p.separated);
    EXPECT_FALSE(p.unfinished);
    EXPECT_EQ(p.free_distance, 0);
    EXPECT_NEAR(p.depth, 1.0, 1e-9);  // out along -x, the least way
    EXPECT_EQ(p.steps, i == 0 ? 1 : 0);
    EXPECT_NEAR(p.direction.norm(), 1.0, 1e-9);
  }
  EXPECT_NE(report.summary.find("already penetrates S at the installed pose"), std::string::npos) << report.summary;
}

TEST(WhatBlocks, StraightPullsNameTheWallsAndTheWayOut) {
  // A rigid peg 2 x 1 x 10 in a pocket: walls 0.5 from it in x and y, a
  // floor 0.3 under it, open above. Pulls along its axes (z, x, y, both
  // ways): up gets out; down stops at the floor, sideways at the walls,
  // each after the clearance plus the tolerance (within a tolerance).
  Scene scene;
  scene.units = "mm";
  scene.dynamic_mesh = MakeBox({-1, -0.5, 0}, {1, 0.5, 10});
  TriangleMesh s = MakeBox({1.5, -5, 0}, {5, 5, 8});
  s.Append(MakeBox({-5, -5, 0}, {-1.5, 5, 8}));
  s.Append(MakeBox({-1.5, 1.0, 0}, {1.5, 5, 8}));
  s.Append(MakeBox({-1.5, -5, 0}, {1.5, -1.0, 8}));
  s.Append(MakeBox({-5, -5, -3}, {5, 5, -0.3}));
  scene.static_mesh = s;
  const double tolerance = 0.05;
  const BlockingReport report = ProbeWhatBlocks(scene, tolerance);
  ASSERT_EQ(report.probes.size(), 6u);
  const double expected_clearance[3] = {0.3, 0.5, 0.5};  // along -z (the floor), x, y
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const BlockingProbe& p = report.probes[2 * axis + side];
      const Eigen::Vector3d along = p.direction.cwiseAbs();
      const int dominant = axis == 0 ? 2 : axis - 1;  // z, then x, then y
      ASSERT_NEAR(along[dominant], 1.0, 1e-9) << "probe " << 2 * axis + side << ": " << p.direction.transpose();
      if (axis == 0 && p.direction.z() > 0) {
        EXPECT_TRUE(p.separated);
        continue;
      }
      EXPECT_FALSE(p.separated) << p.direction.transpose();
      EXPECT_NEAR(p.free_distance, expected_clearance[axis] + tolerance, tolerance) << p.direction.transpose();
      EXPECT_GT(p.depth, tolerance);
      EXPECT_GE(p.rigid_shell, 0);
      EXPECT_GE(p.static_shell, 0);
    }
  }
  ASSERT_GE(report.farthest, 0);
  EXPECT_NEAR(report.probes[report.farthest].free_distance, 0.5 + tolerance, tolerance);
  EXPECT_NE(report.summary.find("5 of 6 straight pulls"), std::string::npos) << report.summary;
}

// A bar 2 x 2 x `length` in its channel, overlapping the walls by 0.03
// (within a 0.05 tolerance; test_bar_in_channel.h).
Scene BarInChannel(double length) { return testing::BarInChannelScene(length, 0.03); }

TEST(WhatBlocks, ALongSlideInContactIsProvedInStretchesNotWalked) {
  // A bar 2 x 2 x 400 in a channel as long as it whose walls it overlaps
  // by 0.03 (within the 0.05 tolerance), a floor 0.3 under it. Pulled up,
  // it slides in contact: by its slack (0.02) per step it would take
  // 20,000 steps, more than kMaxPullSteps; proved in stretches it comes out
  // in a few dozen measurements. Sideways along the walls (y) it comes out
  // after 6; across them (x) and down it is blocked.
  Scene scene = BarInChannel(400);
  const double tolerance = 0.05;
  const BlockingReport report = ProbeWhatBlocks(scene, tolerance);
  ASSERT_EQ(report.probes.size(), 6u);
  ASSERT_TRUE(report.parts->rigid_interference.empty());
  int unfinished = 0, out = 0, blocked = 0;
  for (const BlockingProbe& p : report.probes) {
    const Eigen::Vector3d along = p.direction.cwiseAbs();
    if (p.direction.z() > 0.99) {
      EXPECT_TRUE(p.separated);
      EXPECT_LE(p.steps, 64);
      EXPECT_GE(p.free_distance, 400.0);
    } else if (along.y() > 0.99) {
      EXPECT_TRUE(p.separated) << p.direction.transpose();
      EXPECT_LE(p.steps, 64);
    } else {
      EXPECT_FALSE(p.separated || p.unfinished) << p.direction.transpose();
      EXPECT_LT(p.free_distance, 0.3 + 2 * tolerance) << p.direction.transpose();
    }
    unfinished += p.unfinished;
    out += p.separated;
    blocked += !p.separated && !p.unfinished;
    EXPECT_EQ(p.static_part_name, "");  // S is one part
  }
  EXPECT_EQ(unfinished, 0);
  EXPECT_EQ(out, 3);
  EXPECT_EQ(blocked, 3);
  EXPECT_NE(report.summary.find("3 of 6 straight pulls"), std::string::npos) << report.summary;
  EXPECT_EQ(report.summary.find("unfinished"), std::string::npos) << report.summary;
}

TEST(WhatBlocks, APullThatSlidesInContactReachesThePartAboveAndNamesIt) {
  // A bolt held from above, as in a STEP assembly: the bar 2 x 2 x 40 in
  // its channel (walls overlapping it by 0.03, a floor 0.3 under it; part
  // "channel"), and a cap over the channel 5 above the bar (part "cap").
  // Pulled up, the bar slides in contact for 5, then meets the cap: the
  // pull is blocked there, by the cap, not cut short in the channel.
  Scene scene = BarInChannel(40);
  TriangleMesh& s = scene.static_mesh;
  const std::size_t channel_triangles = s.triangles.size();
  s.Append(MakeBox({-5, -5, 45}, {5, 5, 48}));
  scene.static_part_names = {"channel", "cap"};
  scene.static_part_entry = {0, 1};
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    scene.static_part_of_triangle.push_back(t < channel_triangles ? 0 : 1);
  const double tolerance = 0.05;
  const BlockingReport report = ProbeWhatBlocks(scene, tolerance);
  ASSERT_EQ(report.probes.size(), 6u);
  const BlockingProbe& up = report.probes[0];
  ASSERT_GT(up.direction.z(), 0.99);
  EXPECT_FALSE(up.separated || up.unfinished);
  EXPECT_NEAR(up.free_distance, 5 + tolerance, tolerance);
  EXPECT_LE(up.steps, 120);  // 250 steps of the slack without the stretches
  EXPECT_EQ(up.static_part_name, "cap");
  const BlockingProbe& down = report.probes[1];
  EXPECT_FALSE(down.separated || down.unfinished);
  EXPECT_EQ(down.static_part_name, "channel");
  EXPECT_EQ(report.farthest, 0);
  EXPECT_NE(report.summary.find("of S, part cap"), std::string::npos) << report.summary;
}

// Asked only whether D gets out (what-blocks with a part of S taken away),
// a pull that is too deep one largest step along (5% of D's diagonal) is
// blocked at one depth search; the others are walked as in the report, and
// every pull made gives the report's answer.
TEST(WhatBlocks, AskedOnlyWhetherDGetsOutAPullIntoAWallIsBlockedAtOnce) {
  Scene scene = BarInChannel(40);
  scene.static_mesh.Append(MakeBox({-5, -5, 45}, {5, 5, 48}));  // a cap 5 above the bar
  const double tolerance = 0.05;
  const BlockingReport full = ProbeWhatBlocks(scene, tolerance);
  const BlockingReport quick = ProbeWhatBlocks(scene, tolerance, UnmeasuredInterference::kRigid, nullptr, true);
  ASSERT_EQ(full.probes.size(), 6u);
  ASSERT_FALSE(quick.probes.empty());
  EXPECT_TRUE(quick.probes.back().separated);  // along the walls (y)
  int at_once = 0;
  for (std::size_t i = 0; i < quick.probes.size(); ++i) {
    const BlockingProbe& q = quick.probes[i];
    const BlockingProbe& f = full.probes[i];
    EXPECT_EQ(q.separated, f.separated) << i;
    if (q.separated) continue;
    if (q.direction.z() > 0.99) {  // up: free for 5 (more than a step), then the cap
      EXPECT_NEAR(q.free_distance, 5 + tolerance, tolerance);
      continue;
    }
    // Down onto the floor (0.3 under) or into a wall the bar overlaps.
    EXPECT_EQ(q.steps, 1) << q.direction.transpose();
    EXPECT_EQ(q.free_distance, 0.0);
    EXPECT_GT(q.depth, tolerance);
    EXPECT_GT(f.steps, 5) << f.direction.transpose();
    ++at_once;
  }
  EXPECT_GE(at_once, 1);
}

}  // namespace
}  // namespace ausbau
