// workflow/plan_scene.h ChooseValidity (the pipeline's VALIDITY=auto) on
// hand-sized scenes: a plate D with a dented (non-convex) lug through a
// plate S below it.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "geometry/primitives.h"
#include "scene/scene.h"
#include "workflow/plan_scene.h"

namespace ausbau {
namespace {

// D: a block [-20, 20]^2 x [0, 10] (the anchor) with a non-convex lug
// reaching 4 below it, z down to -4.
TriangleMesh BlockWithDentedLug() {
  TriangleMesh robot = MakeBox({-20, -20, 0}, {20, 20, 10});
  const int base = static_cast<int>(robot.vertices.size());
  for (const Eigen::Vector3d& v :
       std::vector<Eigen::Vector3d>{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, -4}, {0.5, 0.5, -0.5}})
    robot.vertices.push_back(v);
  for (auto tri : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 4, 2}, {2, 4, 3}, {3, 4, 1}}) {
    for (int& i : tri) i += base;
    robot.triangles.push_back(tri);
  }
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
