// A pin pressed a few hundredths of a millimetre into its bore (the CAD
// model of a press fit, or tessellation): rigid-exact plans it out, and the
// exact check of the path passes. Each overlap below the tolerance (0.05 mm)
// was once an internal error ("start pose is in collision": the planners
// check at half the tolerance), and one just below it NOT REMOVABLE (its
// depth, measured to a tenth of the tolerance, came out above it).
#include <gtest/gtest.h>

#include "geometry/primitives.h"
#include "planning/exact_check.h"
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

}  // namespace
}  // namespace ausbau
