// A pin pressed a few hundredths of a millimetre into its bore (the CAD
// model of a press fit, or tessellation): rigid-exact plans it out, and the
// exact check of the path passes. Each overlap below the tolerance (0.05 mm)
// was once an internal error ("start pose is in collision": the planners
// check at half the tolerance), and one just below it NOT REMOVABLE (its
// depth, measured to a tenth of the tolerance, came out above it). A
// headed pin in a tight bore under a bracket comes out in two straight
// pulls.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "collision/fcl_checker.h"
#include "geometry/primitives.h"
#include "planning/exact_check.h"
#include "planning/planner.h"
#include "planning/state_space.h"
#include "scene/scene.h"
#include "workflow/plan_scene.h"

namespace ausbau {
namespace {

Scene PinInPlate(double overlap) {
  Scene scene;
  scene.name = "press-fit";
  scene.units = "mm";
  // The bore: radius 5 through a plate 10 thick; the pin 30 long, its
  // faces parallel to the bore's (both 32-gons): overlap x cos(pi/32) deep.
  scene.dynamic_mesh = MakeSolidOfRevolution({{0, -10}, {5 + overlap, -10}, {5 + overlap, 20}, {0, 20}}, 32);
  scene.static_mesh = MakeSolidOfRevolution({{5, 0}, {25, 0}, {25, 10}, {5, 10}}, 32);
  scene.static_part_names = {"plate"};
  scene.static_part_of_triangle.assign(scene.static_mesh.triangles.size(), 0);
  scene.static_part_entry = {0};
  return scene;
}

TEST(PressFit, APinPressedInWithinTheToleranceComesOut) {
  for (const double overlap : {0.03, 0.045, 0.0495}) {
    const Scene scene = PinInPlate(overlap);
    EXPECT_EQ(ChooseValidity(scene, 0.05), ValidityMode::kRigidExact) << overlap;
    PlanSceneOptions options;
    options.validity = ValidityMode::kRigidExact;
    options.planner.time_limit_s = 30;
    options.planner.seed = 1;
    const PlannedPath planned = PlanScene(scene, options);
    ASSERT_TRUE(planned.artifact.success) << overlap;
    const ExactCheckReport exact = ExactCheckPath(scene, planned.artifact.waypoints, 0.05);
    EXPECT_TRUE(exact.valid) << overlap << ": " << exact.reason;
  }
}

// A headed pin (shank radius 4, 10 long; head radius 6, 3 high, resting on
// the plate) in a bore `gap` wider (negative: pressed in), under a bracket
// whose lid stops a pull up 0.5 after the shank leaves the bore: it lifts
// 10-10.5 and slides out from under the lid. Sampling did not find that
// within 60 s (the shank has hundredths of a mm in its bore, and every check
// there is a surface-depth search); the two-legged straight pull does.
// `closed`: walls on the plate around the pin, under the lid, open only at
// one corner: no slide along an axis gets the pin out, a diagonal one does.
Scene HeadedPinUnderABracket(double gap, bool closed = false) {
  Scene scene;
  scene.name = "pin-under-bracket";
  scene.units = "mm";
  scene.dynamic_mesh = MakeSolidOfRevolution({{0, -10}, {4, -10}, {4, 0}, {6, 0}, {6, 3}, {0, 3}}, 48);
  const double bore = 4 + gap / std::cos(M_PI / 48);  // the faces `gap` apart
  scene.static_mesh = MakeSolidOfRevolution({{bore, -10}, {20, -10}, {20, 0}, {bore, 0}}, 48);
  const std::size_t plate_triangles = scene.static_mesh.triangles.size();
  if (closed) {
    scene.static_mesh.Append(MakeBox({-27, -27, 13.5}, {27, 27, 16.5}));  // the lid
    scene.static_mesh.Append(MakeBox({25, -25, 0.2}, {27, 15, 13.5}));    // walls, open at +x +y
    scene.static_mesh.Append(MakeBox({-25, 25, 0.2}, {15, 27, 13.5}));
    scene.static_mesh.Append(MakeBox({-27, -25, 0.2}, {-25, 25, 13.5}));
    scene.static_mesh.Append(MakeBox({-25, -27, 0.2}, {27, -25, 13.5}));
  } else {
    scene.static_mesh.Append(MakeBox({-8, -15, 13.5}, {30, 15, 16.5}));   // the lid
    scene.static_mesh.Append(MakeBox({-30, -15, -10}, {-21, 15, 16.5}));  // its leg
  }
  scene.static_part_names = {"plate", "bracket"};
  scene.static_part_of_triangle.assign(scene.static_mesh.triangles.size(), 1);
  std::fill_n(scene.static_part_of_triangle.begin(), plate_triangles, 0);
  scene.static_part_entry = {0, 0};
  return scene;
}

TEST(PressFit, AHeadedPinUnderABracketLiftsOutOfItsBoreThenSlidesOut) {
  for (const double gap : {0.02, -0.03}) {
    const Scene scene = HeadedPinUnderABracket(gap);
    PlanSceneOptions options;
    options.validity = ValidityMode::kRigidExact;
    options.planner.time_limit_s = 30;  // a safety net: the pulls count work
    options.planner.seed = 1;
    const PlannedPath planned = PlanScene(scene, options);
    ASSERT_TRUE(planned.artifact.success) << gap;
    EXPECT_LT(planned.artifact.stats.iterations, 100) << gap;  // pulls only, no sampling
    const std::vector<Pose>& path = planned.artifact.waypoints;
    ASSERT_GE(path.size(), 3u) << gap;
    // The first leg straight up, out of the bore and below the lid.
    const Eigen::Vector3d lift = path[1].t - path[0].t;
    EXPECT_NEAR(lift.head<2>().norm(), 0.0, 1e-9) << gap;
    EXPECT_GE(lift.z(), 10.0) << gap;
    EXPECT_LE(lift.z(), 10.5 + 0.05) << gap;
    EXPECT_TRUE(path.back().q.isApprox(path.front().q)) << gap;  // no turn
    const ExactCheckReport exact = ExactCheckPath(scene, path, 0.05);
    EXPECT_TRUE(exact.valid) << gap << ": " << exact.reason;
  }
}

// Where no pull, nor two, gets the pin out from under a closed bracket,
// where they stopped is kept for sampling: the pin lifted out of its bore,
// up to the lid. (Plain collision, the pin raised 0.01 off the plate so
// that its start is free.)
TEST(PressFit, WhereThePullsStopIsKeptForSampling) {
  Scene scene = HeadedPinUnderABracket(0.02, true);
  for (Eigen::Vector3d& v : scene.dynamic_mesh.vertices) v.z() += 0.01;
  const PlanningProblem problem = MakePlanningProblem(scene, 0);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  PlannerOptions options;
  options.seed = 1;
  const PlanResult pulled = TryStraightPulls(problem, checker, options);
  EXPECT_FALSE(pulled.solved());
  const auto lifted = std::find_if(pulled.pull_stops.begin(), pulled.pull_stops.end(), [&](const Pose& stop) {
    const Eigen::Vector3d way = stop.t - problem.start.t;
    return way.head<2>().norm() < 1e-9 && way.z() > 9.99;  // out of the bore
  });
  ASSERT_NE(lifted, pulled.pull_stops.end());
  EXPECT_LE(lifted->t.z() - problem.start.t.z(), 10.5);  // below the lid
  for (const Pose& stop : pulled.pull_stops) EXPECT_TRUE(checker.IsValid(stop));
}

// A start branch is a node of the sampling tree: one in the goal region
// solves the problem before any iteration.
TEST(PressFit, AStartBranchInTheGoalRegionIsThePath) {
  Scene scene = HeadedPinUnderABracket(0.02);
  scene.static_mesh = MakeSolidOfRevolution({{4.02, -10}, {20, -10}, {20, 0}, {4.02, 0}}, 48);  // no bracket
  scene.static_part_names = {"plate"};
  scene.static_part_of_triangle.assign(scene.static_mesh.triangles.size(), 0);
  scene.static_part_entry = {0};
  for (Eigen::Vector3d& v : scene.dynamic_mesh.vertices) v.z() += 0.01;
  const PlanningProblem problem = MakePlanningProblem(scene, 0);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  Pose out = problem.start;
  out.t.z() += 30;
  ASSERT_TRUE(problem.InGoalRegion(out));
  PlannerOptions options;
  options.seed = 1;
  options.start_branches = {out};
  const PlanResult planned = Plan(problem, checker, options);
  ASSERT_TRUE(planned.solved());
  EXPECT_EQ(planned.stats.iterations, 0);
  EXPECT_TRUE(planned.path.back().t.isApprox(out.t));
}

}  // namespace
}  // namespace ausbau
