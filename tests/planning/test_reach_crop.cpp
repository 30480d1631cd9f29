// Cropping S to D's reach (planning/reach_crop.h) on a small generated
// vehicle (fixtures/vehicle.h): the cropped S is small, the planned path is
// valid against the whole S, a riveted part stays blocked, small scenes are
// not cropped.
#include <gtest/gtest.h>

#include <filesystem>

#include "collision/fcl_checker.h"
#include "fixtures/generators.h"
#include "fixtures/vehicle.h"
#include "geometry/primitives.h"
#include "geometry/triangle_box.h"
#include "planning/exact_check.h"
#include "planning/planner.h"
#include "planning/reach_crop.h"
#include "planning/state_space.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "workflow/plan_scene.h"

namespace ausbau {
namespace {

// A shell of ~234k triangles (over kCropMinTriangles), 5 parts: part 4 is
// riveted, the others clipped.
const VehicleModel& SmallVehicle() {
  static const VehicleModel model = [] {
    VehicleOptions options;
    options.parts = 5;
    options.cell = 8.0;
    options.scale = 0.35;
    return MakeVehicle(options);
  }();
  return model;
}

Scene VehicleScene(int part) {
  const VehicleModel& model = SmallVehicle();
  Scene scene;
  scene.file = "vehicle-test/scene.yaml";
  scene.name = "vehicle-test-" + std::to_string(part);
  scene.units = "mm";
  scene.static_mesh = model.shell;
  for (size_t q = 0; q < model.parts.size(); ++q) {
    if (static_cast<int>(q) != part) scene.static_mesh.Append(model.parts[q]);
  }
  scene.dynamic_mesh = model.parts[part];
  return scene;
}

// D's AABB at `pose` (scene convention) grown by `clearance` overlaps no
// triangle of `mesh`: a brute-force pass over the whole S.
bool ClearOfAll(const Scene& scene, const TriangleMesh& mesh, const Pose& pose, double clearance) {
  Aabb box;
  for (const auto& v : scene.dynamic_mesh.vertices) box.Extend(pose.Apply(v - scene.dynamic_origin));
  box.min.array() -= clearance;
  box.max.array() += clearance;
  for (const auto& t : mesh.triangles) {
    if (TriangleOverlapsBox(box.Center(), 0.5 * box.Size(), mesh.vertices[t[0]], mesh.vertices[t[1]],
                            mesh.vertices[t[2]], SatRounding::kPerAxisHalfExtent)) {
      return false;
    }
  }
  return true;
}

TEST(ReachCrop, VehicleGeneratorMakesFastenedParts) {
  const VehicleModel& model = SmallVehicle();
  EXPECT_GT(static_cast<std::int64_t>(model.shell.triangles.size()), kCropMinTriangles);
  ASSERT_EQ(model.parts.size(), 5u);
  EXPECT_FALSE(model.riveted[0]);
  EXPECT_TRUE(model.riveted[4]);
  // Deterministic.
  VehicleOptions options;
  options.parts = 5;
  options.cell = 8.0;
  options.scale = 0.35;
  const VehicleModel again = MakeVehicle(options);
  EXPECT_EQ(again.shell.triangles, model.shell.triangles);
  EXPECT_EQ(again.parts[3].vertices, model.parts[3].vertices);
}

TEST(ReachCrop, PartFarFromMostOfSKeepsFewTriangles) {
  const Scene scene = VehicleScene(0);
  const auto crop = ChooseReachCrop(scene, 0);
  ASSERT_TRUE(crop.has_value());
  const std::int64_t full = static_cast<std::int64_t>(scene.static_mesh.triangles.size());
  EXPECT_EQ(crop->full_triangles, full);
  EXPECT_GT(crop->kept_triangles, 0);
  EXPECT_LT(crop->kept_triangles * 50, full);
  // Level 0: D's installed box grown by 1.5 diagonals.
  const Aabb installed = InstalledBox(scene);
  EXPECT_NEAR(crop->box.min.x(), installed.min.x() - kCropMargin * installed.Diagonal(), 1e-9);
  EXPECT_NEAR(crop->clearance, kCropClearance * installed.Diagonal(), 1e-12);
  // Every triangle it drops lies outside the box grown by the clearance.
  Aabb grown = crop->box;
  grown.min.array() -= crop->clearance;
  grown.max.array() += crop->clearance;
  std::int64_t touching = 0;
  for (const auto& t : scene.static_mesh.triangles) {
    Aabb tbox;
    for (int i : t) tbox.Extend(scene.static_mesh.vertices[i]);
    touching += !tbox.SeparatedFrom(grown);
  }
  EXPECT_EQ(touching, crop->kept_triangles);
  // The next level doubles the margin.
  const auto level1 = ChooseReachCrop(scene, 1);
  ASSERT_TRUE(level1.has_value());
  EXPECT_NEAR(installed.min.x() - level1->box.min.x(), 2 * (installed.min.x() - crop->box.min.x()), 1e-9);
  EXPECT_GT(level1->kept_triangles, crop->kept_triangles);

  // The planning problem: the cropped S, bounds that keep D's ball inside
  // the box, the start (fastened) not in the goal.
  const PlanningProblem problem = MakePlanningProblem(scene);
  ASSERT_NE(problem.crop, nullptr);
  EXPECT_EQ(static_cast<std::int64_t>(problem.environment.triangles.size()), crop->kept_triangles);
  EXPECT_GE(problem.crop->BallSlack(problem.bounds.min, problem.robot_radius), -1e-9);
  EXPECT_GE(problem.crop->BallSlack(problem.bounds.max, problem.robot_radius), -1e-9);
  EXPECT_FALSE(problem.InGoalRegion(problem.start));
  // Lifted 100 mm clear along the roof's normal (+z: part 0 sits on the
  // roof or a side; any axis that clears it will do): in the goal.
  bool some_direction_clears = false;
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {1.0, -1.0}) {
      Pose moved = problem.start;
      moved.t[axis] += sign * 0.7 * (crop->box.Size()[axis] / 2 - problem.robot_radius);
      if (problem.InBounds(moved) && problem.InGoalRegion(moved)) some_direction_clears = true;
    }
  }
  EXPECT_TRUE(some_direction_clears);
}

TEST(ReachCrop, PlannedPathIsValidAgainstTheWholeS) {
  const Scene scene = VehicleScene(0);
  PlanSceneOptions options;
  options.validity = ValidityMode::kRigidExact;
  options.planner.time_limit_s = 30;
  options.planner.seed = 1;
  const PlannedPath planned = PlanScene(scene, options);
  ASSERT_TRUE(planned.artifact.success);
  const std::vector<Pose>& path = planned.artifact.waypoints;
  // The exact check, within the smallest crop that holds the path.
  const ExactCheckReport cropped = ExactCheckPath(scene, path, 0.05);
  EXPECT_TRUE(cropped.valid) << cropped.reason;
  EXPECT_EQ(cropped.crop_level, 0);
  // The same check against the whole S (bounds in the scene turn the crop
  // off): no rigid penetration anywhere along the path ...
  Scene whole = scene;
  Aabb everything;
  everything.min = Eigen::Vector3d::Constant(-1e7);
  everything.max = Eigen::Vector3d::Constant(1e7);
  whole.bounds = everything;
  const ExactCheckReport full = ExactCheckPath(whole, path, 0.05);
  EXPECT_EQ(full.crop_level, -1);
  EXPECT_EQ(full.checked_triangles, static_cast<std::int64_t>(scene.static_mesh.triangles.size()));
  EXPECT_TRUE(full.starts_at_start);
  EXPECT_LE(full.max_rigid_depth, 0.05);
  EXPECT_LT(full.first_bad_segment, 0);
  // ... and it ends at least the clearance away from every triangle of S.
  const auto crop = ChooseReachCrop(scene, 0);
  ASSERT_TRUE(crop.has_value());
  EXPECT_TRUE(ClearOfAll(scene, scene.static_mesh, path.back(), crop->clearance));
  EXPECT_FALSE(ClearOfAll(scene, scene.static_mesh, path.front(), crop->clearance));
}

// A pin (radius 4.9, 20 long) in the middle of a tube (bore radius 5, 600
// long, 205k triangles): it comes out by sliding 310 along the axis, far
// beyond the level-0 crop (about 46 either side), which holds only a piece
// of the tube around it. Its straight pull is free up to each crop's edge,
// so the crop grows at once (levels 0-2 without sampling) until the whole
// tube is in, where the pull gets it out. Before, each level sampled its
// 61,440 iterations first, in a bore of 0.1 clearance: no path in 60 s.
TEST(ReachCrop, APinInATubeLongerThanTheCropComesOutAlongIt) {
  std::vector<Eigen::Vector2d> profile;  // (r, z): the bore up, the outside down
  constexpr int kRings = 800;
  for (int i = 0; i <= kRings; ++i) profile.emplace_back(5.0, -300.0 + 600.0 * i / kRings);
  for (int i = kRings; i >= 0; --i) profile.emplace_back(10.0, -300.0 + 600.0 * i / kRings);
  Scene scene;
  scene.file = "pin-in-tube/scene.yaml";
  scene.name = "pin-in-tube";
  scene.units = "mm";
  scene.static_mesh = MakeSolidOfRevolution(profile, 64);
  ASSERT_GT(static_cast<std::int64_t>(scene.static_mesh.triangles.size()), kCropMinTriangles);
  scene.dynamic_mesh = MakeSolidOfRevolution({{0, -10}, {4.9, -10}, {4.9, 10}, {0, 10}}, 64);
  ASSERT_TRUE(ChooseReachCrop(scene, 0).has_value());
  PlanSceneOptions options;
  options.validity = ValidityMode::kRigidExact;
  options.planner.time_limit_s = 600;  // a safety net only: the answer is the work's
  options.planner.seed = 1;
  const PlannedPath planned = PlanScene(scene, options);
  ASSERT_TRUE(planned.artifact.success);
  const std::vector<Pose>& path = planned.artifact.waypoints;
  ASSERT_GE(path.size(), 2u);
  EXPECT_GT(std::abs(path.back().t.z()), 300.0);  // out of the tube along its axis
  EXPECT_NEAR(path.back().t.x(), 0.0, 1e-9);
  EXPECT_LT(planned.artifact.stats.iterations, 100);  // pulls only, no sampling
  const ExactCheckReport check = ExactCheckPath(scene, path, 0.05);
  EXPECT_TRUE(check.valid) << check.reason;
}

// A bar lying on a wide disc of S (over kCropMinTriangles, so cropped;
// a post beside it, so that S's box rises above it): its pulls along its
// length stay on the disc to the crop's edge, its pull up gets it out. Whether a pull is free to the crop's edge is
// asked only once no pull got D out (each such pull, walked along a contact, may cost a surface-depth search per
// stretch); here one did, so it is not asked.
TEST(ReachCrop, PullsToTheCropsEdgeAreWalkedOnlyWhereNoPullGetsDOut) {
  std::vector<Eigen::Vector2d> profile;  // (r, z): a disc 2 thick, its top at z = 0
  constexpr int kRings = 800;
  for (int i = 0; i <= kRings; ++i) profile.emplace_back(300.0 * i / kRings, 0.0);
  for (int i = kRings; i >= 0; --i) profile.emplace_back(300.0 * i / kRings, -2.0);
  Scene scene;
  scene.file = "bar-on-disc/scene.yaml";
  scene.name = "bar-on-disc";
  scene.units = "mm";
  scene.static_mesh = MakeSolidOfRevolution(profile, 64);
  scene.static_mesh.Append(MakeBox({-5, 20, 0}, {5, 25, 30}));  // a post beside the bar
  ASSERT_GT(static_cast<std::int64_t>(scene.static_mesh.triangles.size()), kCropMinTriangles);
  scene.dynamic_mesh = MakeBox({-20, -4, 0.05}, {20, 4, 8.05});  // 0.05 above the disc
  const PlanningProblem problem = MakePlanningProblem(scene, 0);
  ASSERT_NE(problem.crop, nullptr);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  PlannerOptions options;
  options.seed = 1;
  const PlanResult pulled = TryStraightPulls(problem, checker, options);
  ASSERT_TRUE(pulled.solved());
  const Eigen::Vector3d pull = pulled.path.back().t - pulled.path.front().t;
  EXPECT_GT(pull.z(), 0.0);  // up, off the disc
  EXPECT_NEAR(pull.head<2>().norm(), 0.0, 1e-9);
  EXPECT_FALSE(pulled.pull_left_crop);
  // Without the pull up (D under a lid just above it), the bar's pulls
  // along the disc are free to the crop's edge, and that is said.
  Scene covered = scene;
  covered.static_mesh.Append(MakeBox({-30, -30, 8.1}, {30, 30, 10}));
  const PlanningProblem lidded = MakePlanningProblem(covered, 0);
  ASSERT_NE(lidded.crop, nullptr);
  const FclCollisionChecker lid_checker(lidded.robot, lidded.environment);
  const PlanResult blocked = TryStraightPulls(lidded, lid_checker, options);
  EXPECT_FALSE(blocked.solved());
  EXPECT_TRUE(blocked.pull_left_crop);
}

TEST(ReachCrop, RivetedPartStaysBlocked) {
  const Scene scene = VehicleScene(4);
  PlanSceneOptions options;
  options.validity = ValidityMode::kRigidExact;
  options.planner.time_limit_s = 2;
  options.planner.seed = 1;
  options.max_crop_level = 1;
  const PlannedPath planned = PlanScene(scene, options);
  EXPECT_FALSE(planned.artifact.success);
}

TEST(ReachCrop, ExactCheckRejectsAnEndThatIsNotClear) {
  // The installed pose alone: inside the crop, but not clear of S.
  const Scene scene = VehicleScene(0);
  const ExactCheckReport report = ExactCheckPath(scene, {scene.start}, 0.05);
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.crop_level, 0);
  EXPECT_NE(report.reason.find("clear of S"), std::string::npos) << report.reason;
}

TEST(ReachCrop, SmootherTakesTheLevelThatHoldsThePath) {
  const Scene scene = VehicleScene(0);
  const PlanningProblem level0 = MakePlanningProblem(scene, 0);
  ASSERT_NE(level0.crop, nullptr);
  // A waypoint just beyond level 0's bounds (along the axis of the largest
  // room) lies inside level 1's.
  Pose far = scene.start;
  far.t.x() += level0.bounds.max.x() - level0.start.t.x() + 1.0;
  EXPECT_FALSE(level0.InBounds(level0.SceneToPlanning(far)));
  const PlanningProblem holding = MakePlanningProblemHolding(scene, {scene.start, far});
  ASSERT_NE(holding.crop, nullptr);
  EXPECT_EQ(holding.crop->level, 1);
  EXPECT_EQ(MakePlanningProblemHolding(scene, {scene.start}).crop->level, 0);
}

TEST(ReachCrop, SmallScenesAndScenesWithBoundsAreNotCropped) {
  const testing::ScopedTempDir dir("reach-crop");  // removed at the end of the test, also after a failure
  const Scene small = LoadScene(GenerateScene("peg-in-plate", 1, dir.path()));
  EXPECT_FALSE(ChooseReachCrop(small, 0).has_value());
  EXPECT_EQ(MakePlanningProblem(small).crop, nullptr);

  Scene bounded = VehicleScene(0);
  Aabb bounds;
  bounds.min = Eigen::Vector3d::Constant(-1e5);
  bounds.max = Eigen::Vector3d::Constant(1e5);
  bounded.bounds = bounds;
  EXPECT_FALSE(ChooseReachCrop(bounded, 0).has_value());
  // A level whose box holds all of S is the uncropped scene.
  EXPECT_FALSE(ChooseReachCrop(VehicleScene(0), 30).has_value());
}

}  // namespace
}  // namespace ausbau
