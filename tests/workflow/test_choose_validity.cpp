// workflow/plan_scene.h ChooseValidity (the pipeline's VALIDITY=auto) on
// hand-sized scenes: a plate D with a dented (non-convex) lug through a
// plate S below it.
#include <gtest/gtest.h>

#include "geometry/primitives.h"
#include "scene/scene.h"
#include "test_dented_lug.h"
#include "workflow/plan_scene.h"

namespace ausbau {
namespace {

// D: a block [-20, 20]^2 x [0, 10] (the anchor) with a non-convex lug
// reaching 4 below it, z down to -4.
TriangleMesh BlockWithDentedLug() {
  TriangleMesh robot = MakeBox({-20, -20, 0}, {20, 20, 10});
  testing::AppendDentedLug(&robot);
  return robot;
}

Scene SceneOf(const TriangleMesh& robot, const TriangleMesh& environment) {
  Scene scene;
  scene.name = "choose-validity";
  scene.units = "mm";
  scene.dynamic_mesh = robot;
  scene.static_mesh = environment;
  scene.static_part_names = {"plate"};
  scene.static_part_of_triangle.assign(environment.triangles.size(), 0);
  scene.static_part_entry = {0};
  return scene;
}

TEST(ChooseValidity, ANonConvexLugThroughSNeedsTheVolumeModel) {
  // S's plate, z in [-3, -1]: only the lug reaches into it (3 deep).
  const Scene scene = SceneOf(BlockWithDentedLug(), MakeBox({-30, -30, -3}, {30, 30, -1}));
  EXPECT_EQ(ChooseValidity(scene, 0.05), ValidityMode::kLabeledMliv);
}

TEST(ChooseValidity, AClashOfTheAnchorIsRigidExactWhateverTheLugs) {
  // S's plate, z in [-3, 4]: the block itself sits 4 deep in it, more than a
  // fit may be (5% of its 58 mm diagonal), so the verdict's exact check
  // refuses any path in either validity: the volume model would only take
  // longer to say so.
  const Scene scene = SceneOf(BlockWithDentedLug(), MakeBox({-30, -30, -3}, {30, 30, 4}));
  EXPECT_EQ(ChooseValidity(scene, 0.05), ValidityMode::kRigidExact);
}

TEST(ChooseValidity, NothingThroughSIsRigidExact) {
  const Scene scene = SceneOf(BlockWithDentedLug(), MakeBox({-30, -30, -9}, {30, 30, -5}));
  EXPECT_EQ(ChooseValidity(scene, 0.05), ValidityMode::kRigidExact);
}

}  // namespace
}  // namespace ausbau
