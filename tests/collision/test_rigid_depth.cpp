// Shells, the exact separating-axis depth and the rigid/fastener rule, on
// hand-checkable boxes.
#include <gtest/gtest.h>

#include <cmath>

#include "collision/rigid_depth.h"
#include "fixtures/box_scenes.h"
#include "geometry/primitives.h"
#include "geometry/shells.h"
#include "test_dented_lug.h"
#include "test_key_scene.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using testing::PoseAt;

TEST(Shells, BoxSoupSplitsIntoConvexBoxes) {
  TriangleMesh soup = MakeBox({0, 0, 0}, {10, 10, 1});
  soup.Append(MakeBox({2, 2, 0.5}, {3, 3, 5}));  // overlaps the first: still its own shell
  const auto shells = SplitIntoShells(soup);
  ASSERT_EQ(shells.size(), 2u);
  for (const auto& s : shells) {
    EXPECT_TRUE(s.closed);
    EXPECT_TRUE(s.convex);
    EXPECT_EQ(s.face_normals.size(), 3u);
    EXPECT_EQ(s.edge_directions.size(), 3u);
    EXPECT_EQ(s.corners.size(), 8u);
  }
  EXPECT_NEAR(shells[0].volume, 100, 1e-9);
  EXPECT_NEAR(shells[1].volume, 4.5, 1e-9);
}

TEST(Shells, AFineCylindersFacetsAreFacesOfTheirOwn) {
  // 2048 facets: neighbouring normals 3.1e-3 rad apart, more than the 1e-3
  // that makes two directions one, so every facet is a face (up to sign:
  // 1024 side directions and the caps' one) and every rim edge a feature
  // edge (1024 directions and the axis). Found through a grid of
  // directions, where a search through all of them made a curved shell's
  // analysis quadratic in its triangles.
  const auto shells = SplitIntoShells(MakeSolidOfRevolution({{0, 0}, {5, 0}, {5, 10}, {0, 10}}, 2048));
  ASSERT_EQ(shells.size(), 1u);
  EXPECT_TRUE(shells[0].convex);
  EXPECT_EQ(shells[0].face_normals.size(), 1025u);
  EXPECT_EQ(shells[0].edge_directions.size(), 1025u);
  EXPECT_EQ(shells[0].corners.size(), 2u * 2048);
  for (const Eigen::Vector3d& normal : shells[0].face_normals) EXPECT_NEAR(normal.norm(), 1, 1e-12);
}

TEST(Shells, FineTessellationHasTheSameAxesAndDepth) {
  const auto coarse = SplitIntoShells(MakeBox({0, 0, 0}, {4, 2, 1}));
  OrientedBox box;  // the generators' finely tessellated box: 4 x 4 squares and more per face
  box.center = {2, 1, 0.5};
  box.half_extents = {2, 1, 0.5};
  const auto fine = SplitIntoShells(BoxShell(box, BoxTessellation::kFine));
  ASSERT_EQ(fine.size(), 1u);
  EXPECT_TRUE(fine[0].convex);
  EXPECT_EQ(fine[0].face_normals.size(), 3u);
  EXPECT_EQ(fine[0].edge_directions.size(), 3u);
  EXPECT_EQ(fine[0].corners.size(), 8u);
  const auto other = SplitIntoShells(MakeBox({3.7, 1, 0.5}, {6, 3, 2}));
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  EXPECT_NEAR(ConvexSignedDepth(coarse[0], identity, other[0]), 0.3, 1e-12);  // overlap 0.3 in x, 1 in y, 0.5 in z
  EXPECT_NEAR(ConvexSignedDepth(fine[0], identity, other[0]), 0.3, 1e-12);
}

TEST(Shells, FineBoxesMetresAwayInSinglePrecisionStayConvexShells) {
  // Two finely tessellated boxes flush along an edge (a rail's leg and foot),
  // turned and placed 4 m from the origin, every coordinate rounded to float
  // as an STL file stores it, each triangle with its own corners.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  OrientedBox leg, foot;
  leg.rotation = foot.rotation = turn;
  leg.half_extents = {1.5, 15, 4};
  foot.half_extents = {3.5, 15, 1.2};
  leg.center = Eigen::Vector3d(3000, -2000, 1500);
  foot.center = leg.center + turn * Eigen::Vector3d(2, 0, -2.8);  // flush at the leg's outer bottom edge
  TriangleMesh soup;
  for (const OrientedBox* box : {&leg, &foot}) {
    const TriangleMesh shell = BoxShell(*box, BoxTessellation::kFine);
    for (const auto& tri : shell.triangles) {
      std::array<int, 3> own;
      for (int k = 0; k < 3; ++k) {
        own[k] = static_cast<int>(soup.vertices.size());
        soup.vertices.push_back(shell.vertices[tri[k]].cast<float>().cast<double>());
      }
      soup.triangles.push_back(own);
    }
  }
  const auto shells = SplitIntoShells(soup);
  ASSERT_EQ(shells.size(), 2u);
  for (const auto& shell : shells) {
    EXPECT_TRUE(shell.closed);
    EXPECT_TRUE(shell.convex);
    EXPECT_EQ(shell.corners.size(), 8u);
  }
  // Moved about its own centre (a planner's frame), the rounding it was
  // stored with stays: the tolerances follow the stored magnitude.
  TriangleMesh centred = soup;
  for (auto& v : centred.vertices) v -= leg.center;
  for (const auto& shell : SplitIntoShells(centred, leg.center.norm())) EXPECT_TRUE(shell.convex);
}

TEST(Shells, ASliverThinnerThanTheWeldBelongsToNoShell) {
  // A 10 mm cube 3 m from the origin (welds within 1e-6 of that: 3e-3 mm)
  // whose top face is a fan about a point e 1e-3 mm from its corner a, as a
  // boolean's rounding leaves it: the two fan triangles through a and e are
  // slivers; welded, e is a and they have no area and no edges.
  const Eigen::Vector3d o(3000, 0, 0);
  TriangleMesh cube = MakeBox(o, o + Eigen::Vector3d(10, 10, 10));
  // Drop the two top triangles (z = 10) and write the fan instead.
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : cube.triangles) {
    bool top = true;
    for (int v : t) top = top && cube.vertices[v].z() == 10;
    if (!top) kept.push_back(t);
  }
  ASSERT_EQ(kept.size(), 10u);
  cube.triangles = kept;
  auto index_of = [&](const Eigen::Vector3d& p) {
    for (int v = 0; v < static_cast<int>(cube.vertices.size()); ++v)
      if (cube.vertices[v] == p) return v;
    return -1;
  };
  const int a = index_of(o + Eigen::Vector3d(0, 0, 10)), b = index_of(o + Eigen::Vector3d(10, 0, 10)),
            c = index_of(o + Eigen::Vector3d(10, 10, 10)), d = index_of(o + Eigen::Vector3d(0, 10, 10));
  ASSERT_TRUE(a >= 0 && b >= 0 && c >= 0 && d >= 0);
  const int e = static_cast<int>(cube.vertices.size());
  cube.vertices.push_back(o + Eigen::Vector3d(1e-3, 0.5e-3, 10));
  for (const std::array<int, 3>& t : {std::array<int, 3>{a, b, e}, {b, c, e}, {c, d, e}, {d, a, e}})
    cube.triangles.push_back(t);
  const auto shells = SplitIntoShells(cube);
  ASSERT_EQ(shells.size(), 1u);
  EXPECT_TRUE(shells[0].closed);
  EXPECT_TRUE(shells[0].convex);
  EXPECT_EQ(shells[0].triangles.size(), 12u);  // the slivers (a, b, e) and (d, a, e) are left out
  EXPECT_NEAR(shells[0].volume, 1000, 1e-6);
}

TEST(Shells, NonConvexAndOpenShellsAreFlagged) {
  TriangleMesh open = MakeBox({0, 0, 0}, {1, 1, 1});
  open.triangles.pop_back();
  EXPECT_FALSE(SplitIntoShells(open)[0].closed);
  EXPECT_FALSE(SplitIntoShells(open)[0].convex);
  // An L: two boxes sharing a face, welded into one closed non-convex shell
  // is hard to build by hand; a tetrahedron with a dent is enough.
  TriangleMesh dented;
  dented.vertices = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {0.5, 0.5, 0.5}};
  // Tetrahedron whose face (1,2,3) is replaced by three faces through the
  // inner point 4: a dent.
  dented.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 4}, {2, 3, 4}, {3, 1, 4}};
  const auto shells = SplitIntoShells(dented);
  ASSERT_EQ(shells.size(), 1u);
  EXPECT_TRUE(shells[0].closed);
  EXPECT_FALSE(shells[0].convex);
}

TEST(Shells, SignedDepthIsExactForTurnedBoxesAndAGap) {
  const auto a = SplitIntoShells(MakeBox({-1, -1, -1}, {1, 1, 1}));
  const auto b = SplitIntoShells(MakeBox({-1, -1, -1}, {1, 1, 1}));
  // Side by side with a gap of 0.25 along x.
  EXPECT_NEAR(ConvexSignedDepth(a[0], PoseAt(2.25, 0, 0).ToIsometry(), b[0]), -0.25, 1e-12);
  // Turned 45 degrees about z: its corner reaches sqrt(2) from its centre.
  const double reach = std::sqrt(2.0);
  EXPECT_NEAR(ConvexSignedDepth(a[0], PoseAt(1 + reach - 0.1, 0, 0, M_PI / 4).ToIsometry(), b[0]), 0.1, 1e-9);
  // Edge against edge: A turned 45 degrees about z (its leftmost feature an
  // edge along z at x - sqrt 2), B about y (its rightmost an edge along y at
  // sqrt 2): the edges cross, 0.2 deep along x.
  const Eigen::Isometry3d b_turned(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY()));
  std::vector<Shell> b_moved = b;
  for (auto* list : {&b_moved[0].corners, &b_moved[0].vertices})
    for (auto& p : *list) p = b_turned * p;
  for (auto& n : b_moved[0].face_normals) n = b_turned.linear() * n;
  for (auto& e : b_moved[0].edge_directions) e = b_turned.linear() * e;
  EXPECT_NEAR(ConvexSignedDepth(a[0], PoseAt(2 * reach - 0.2, 0, 0, M_PI / 4).ToIsometry(), b_moved[0]), 0.2, 1e-9);
}

using testing::KeyScene;  // a rigid key through a slot in a 2 mm plate (test_key_scene.h)

TEST(RigidDepth, ARigidKeyCannotCrossATwoMillimetrePlate) {
  const KeyScene scene;
  const auto parts = ClassifyParts(scene.robot, scene.environment, Pose{}, 0.05);
  EXPECT_EQ(parts->FastenerCount(), 0);  // nothing intersects at the installed pose: all rigid
  EXPECT_TRUE(parts->rigid_interference.empty());
  const RigidDepthChecker checker(parts, 0.05, 0.01);
  EXPECT_TRUE(checker.IsValid(Pose{}));
  EXPECT_NEAR(checker.Measure(Pose{}).rigid_depth, -0.5, 1e-12);  // the slot's clearance
  // Sideways by 1 mm: the key cuts 0.5 mm into the plate, whatever any volume threshold says.
  const DepthReport cut = checker.Measure(PoseAt(1.0, 0, 0));
  EXPECT_NEAR(cut.rigid_depth, 0.5, 1e-12);
  EXPECT_FALSE(checker.IsValid(PoseAt(1.0, 0, 0)));
  EXPECT_TRUE(checker.IsValid(PoseAt(0.52, 0, 0)));  // 0.02 deep: within the limit 0.05
  EXPECT_FALSE(checker.IsValid(PoseAt(0.56, 0, 0)));
  // Pulled straight up it stays clear.
  EXPECT_TRUE(checker.IsValid(PoseAt(0, 0, 30)));
}

// An L (non-convex) resting on a plate, 0.5 mm from a wall: the planners'
// check (NewContacts::kCollide) measures the contact the installed pose has
// (the plate) but takes any meeting with the wall for a collision; the exact
// check (kMeasure) allows both up to its limit.
TEST(RigidDepth, NewContactsOfANonConvexPartCollideWhilePlanning) {
  const TriangleMesh robot = MakePrism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 5}, {0, 5}}, 0, 2);
  TriangleMesh environment = MakeBox({-10, -10, -1}, {10, 10, 0});  // the plate: D rests on it
  environment.Append(MakeBox({4.5, -10, 0}, {10, 10, 5}));          // the wall, 0.5 mm off the foot
  const auto parts = ClassifyParts(robot, environment, Pose{}, 0.05);
  ASSERT_EQ(parts->robot_shells.size(), 1u);
  EXPECT_FALSE(parts->robot_shells[0].convex);
  EXPECT_TRUE(parts->InstalledContact(0, 0));
  EXPECT_FALSE(parts->InstalledContact(0, 1));
  const RigidDepthChecker exact(parts, 0.05, 0.01), planning(parts, 0.05, 0.01, NewContacts::kCollide);
  for (const RigidDepthChecker* checker : {&exact, &planning}) {
    EXPECT_TRUE(checker->IsValid(Pose{}));
    EXPECT_TRUE(checker->IsValid(PoseAt(0, 0, -0.02)));  // 0.02 into the plate it rests on
    EXPECT_TRUE(checker->IsValid(PoseAt(0.4, 0, 0)));    // 0.1 from the wall
    EXPECT_FALSE(checker->IsValid(PoseAt(0.6, 0, 0)));   // 0.1 into the wall
    EXPECT_GT(checker->MeasureSlack(PoseAt(0.4, 0, 0)), 0);
  }
  // 0.02 into the wall: within the limit for the exact check, a new contact
  // for the planners'.
  EXPECT_TRUE(exact.IsValid(PoseAt(0.52, 0, 0)));
  EXPECT_FALSE(planning.IsValid(PoseAt(0.52, 0, 0)));
  EXPECT_LT(planning.MeasureSlack(PoseAt(0.52, 0, 0)), 0);
  EXPECT_NEAR(exact.Measure(PoseAt(0.52, 0, 0)).rigid_depth, 0.02, 0.005);
}

// The same S classified again, with D in another frame (the exact check
// after a search): S's shells and models are the first classification's,
// and every answer is the same as from models of its own. A different S
// (another crop of it) gets its own.
TEST(RigidDepth, TheSameSClassifiedAgainSharesItsModels) {
  const TriangleMesh robot = MakePrism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 5}, {0, 5}}, 0, 2);
  TriangleMesh environment = MakeBox({-10, -10, -1}, {10, 10, 0});
  environment.Append(MakeBox({4.5, -10, 0}, {10, 10, 5}));
  const auto first = ClassifyParts(robot, environment, Pose{}, 0.05);
  TriangleMesh shifted = robot;  // D about another reference point
  for (auto& v : shifted.vertices) v -= Eigen::Vector3d(2, 1, 0);
  const auto again = ClassifyParts(shifted, environment, PoseAt(2, 1, 0), 0.05);
  EXPECT_TRUE(SharesStaticModels(*first, *again));
  auto own = std::make_shared<PartModel>(*again);
  own->shell_models = nullptr;  // a checker builds its own
  const RigidDepthChecker shared(again, 0.05, 0.01), separate(own, 0.05, 0.01);
  for (double x : {0.0, 0.4, 0.52, 0.6}) {
    for (double z : {-0.03, 0.0, 0.5}) {
      EXPECT_EQ(shared.MeasureSlack(PoseAt(2 + x, 1, z)), separate.MeasureSlack(PoseAt(2 + x, 1, z))) << x << " " << z;
    }
  }
  TriangleMesh cropped = environment;
  cropped.cropped_to = Aabb{Eigen::Vector3d::Constant(-20), Eigen::Vector3d::Constant(20)};
  EXPECT_FALSE(SharesStaticModels(*first, *ClassifyParts(robot, cropped, Pose{}, 0.05)));
}

// A convex pin (radius 4.9) in the bore (radius 5) of a tube 600 long: the
// check proves the pair apart from the tube's triangles near the pin alone
// (it once scanned all of S, the tube's radius as its reach); the answers
// at the middle and near an end, centred, a hair off and cutting in.
TEST(RigidDepth, APinInALongTubesBoreIsClearUntilItCutsIn) {
  const TriangleMesh pin = MakeSolidOfRevolution({{0, -10}, {4.9, -10}, {4.9, 10}, {0, 10}}, 32);
  const TriangleMesh tube = MakeSolidOfRevolution({{5, -300}, {10, -300}, {10, 300}, {5, 300}}, 32);
  const auto parts = ClassifyParts(pin, tube, Pose{}, 0.05);
  ASSERT_EQ(parts->robot_shells.size(), 1u);
  EXPECT_TRUE(parts->robot_shells[0].convex);
  EXPECT_FALSE(parts->static_shells[0].convex);
  for (const NewContacts contacts : {NewContacts::kMeasure, NewContacts::kCollide}) {
    const RigidDepthChecker checker(parts, 0.05, 0.01, contacts);
    for (const double z : {0.0, 250.0, -285.0}) {
      EXPECT_TRUE(checker.IsValid(PoseAt(0, 0, z))) << z;
      EXPECT_TRUE(checker.IsValid(PoseAt(0.03, 0, z))) << z;  // still clear of the bore
      EXPECT_FALSE(checker.IsValid(PoseAt(0.5, 0, z))) << z;  // 0.4 into the tube
      EXPECT_FALSE(checker.IsValid(PoseAt(0, -0.5, z))) << z;
    }
    EXPECT_TRUE(checker.IsValid(PoseAt(0.5, 0, 320)));  // out of the tube's end
  }
}

// ClassifyParts builds the shells' models (FCL trees, depth surfaces) for
// its own measurements and keeps them in the PartModel; every checker of
// that model reuses them. A model without them (made by hand) gets its own:
// the same answers either way.
TEST(RigidDepth, CheckersReuseTheModelsTheClassificationBuilt) {
  const TriangleMesh robot = MakePrism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 5}, {0, 5}}, 0, 2);
  TriangleMesh environment = MakeBox({-10, -10, -1}, {10, 10, 0});
  environment.Append(MakeBox({4.5, -10, 0}, {10, 10, 5}));
  const auto parts = ClassifyParts(robot, environment, Pose{}, 0.05);
  ASSERT_NE(parts->shell_models, nullptr);  // a non-convex shell: models built
  auto bare = std::make_shared<PartModel>(*parts);
  bare->shell_models = nullptr;
  const RigidDepthChecker shared(parts, 0.05, 0.01, NewContacts::kCollide);
  const RigidDepthChecker own(bare, 0.05, 0.01, NewContacts::kCollide);
  for (double x : {0.0, 0.2, 0.4, 0.45, 0.49, 0.52, 0.6, 1.0}) {
    for (double z : {-0.03, -0.01, 0.0, 0.5}) {
      const Pose pose = PoseAt(x, 0, z);
      EXPECT_EQ(shared.MeasureSlack(pose), own.MeasureSlack(pose)) << x << " " << z;
      EXPECT_EQ(shared.ProveTranslation(pose, Eigen::Vector3d(0.3, 0, 0)),
                own.ProveTranslation(pose, Eigen::Vector3d(0.3, 0, 0)))
          << x << " " << z;
    }
  }
}

TEST(RigidDepth, ClipsThatInterfereAreFastenersAndMayNotCutDeeper) {
  TriangleMesh robot = MakeBox({-50, -50, 1}, {50, 50, 4});  // panel (anchor)
  robot.Append(MakeBox({-0.75, -5, -4}, {0.75, 5, 1.5}));    // clip beam, in a 4 mm wide hole
  robot.Append(MakeBox({-0.7, -5, -3.9}, {3, 5, -1.5}));     // hook: 1 mm under the rim, 0.5 mm into it
  robot.Append(MakeBox({20, -5, -3}, {22, 5, 1.5}));         // a rigid rib in its own hole
  TriangleMesh environment = MakeBox({-100, -100, -2}, {-2, 100, 0});
  environment.Append(MakeBox({2, -100, -2}, {19, 100, 0}));
  environment.Append(MakeBox({-2, -100, -2}, {2, -6, 0}));
  environment.Append(MakeBox({-2, 6, -2}, {2, 100, 0}));
  environment.Append(MakeBox({23, -100, -2}, {100, 100, 0}));
  environment.Append(MakeBox({19, -100, -2}, {23, -6, 0}));
  environment.Append(MakeBox({19, 6, -2}, {23, 100, 0}));
  const auto parts = ClassifyParts(robot, environment, Pose{}, 0.05);
  ASSERT_EQ(parts->robot_shells.size(), 4u);
  EXPECT_EQ(parts->anchor, 0);
  EXPECT_EQ(parts->role[0], ShellRole::kRigid);
  EXPECT_EQ(parts->role[1], ShellRole::kFastener);  // the beam: overlaps the hook
  EXPECT_EQ(parts->role[2], ShellRole::kFastener);  // the hook: interferes
  EXPECT_EQ(parts->role[3], ShellRole::kRigid);     // the rib: clear of S
  EXPECT_TRUE(parts->rigid_interference.empty());
  ASSERT_EQ(parts->cluster_limit.size(), 1u);
  EXPECT_NEAR(parts->installed_depth[2], 0.5, 1e-12);  // hook 0.5 mm into the plate's underside
  const RigidDepthChecker checker(parts, 0.025, 0.01);
  EXPECT_TRUE(checker.IsValid(Pose{}));
  const DepthReport pulled = checker.Measure(PoseAt(0, 0, 1.0));  // the hook passes the rim: the clip bends 1 mm
  EXPECT_TRUE(checker.IsValid(PoseAt(0, 0, 1.0)));
  EXPECT_NEAR(pulled.fastener_depth, 1.0, 1e-12);     // reported, not judged
  EXPECT_FALSE(checker.IsValid(PoseAt(-1.5, 0, 0)));  // sideways: the rib hits its hole
  EXPECT_EQ(checker.Measure(PoseAt(-1.5, 0, 0)).rigid_shell, 3);
}

TEST(RigidDepth, AFastenerBendsOnlyIntoTheSolidItEngages) {
  // The clip of the test above, and under its hook, 0.3 mm below it, a
  // bracket apart from the plate (2.2 mm under it): a solid of S the clip
  // does not engage at the installed pose.
  TriangleMesh robot = MakeBox({-50, -50, 1}, {50, 50, 4});            // panel (anchor)
  robot.Append(MakeBox({-0.75, -5, -4}, {0.75, 5, 1.5}));              // clip beam
  robot.Append(MakeBox({-0.7, -5, -3.9}, {3, 5, -1.5}));               // hook, 0.5 mm into the rim
  TriangleMesh environment = MakeBox({-100, -100, -2}, {-2, 100, 0});  // the plate: five boxes that touch
  environment.Append(MakeBox({2, -100, -2}, {100, 100, 0}));
  environment.Append(MakeBox({-2, -100, -2}, {2, -6, 0}));
  environment.Append(MakeBox({-2, 6, -2}, {2, 100, 0}));
  environment.Append(MakeBox({-1, -5, -8}, {4, 5, -4.2}));  // the bracket
  const auto parts = ClassifyParts(robot, environment, Pose{}, 0.05);
  ASSERT_EQ(parts->static_solid.size(), 5u);
  EXPECT_EQ(parts->static_solid, (std::vector<int>{0, 0, 0, 0, 1}));
  ASSERT_EQ(parts->cluster_engages.size(), 1u);
  EXPECT_EQ(parts->cluster_engages[0], std::vector<int>{0});
  EXPECT_TRUE(parts->Engages(2, 1));
  EXPECT_FALSE(parts->Engages(2, 4));
  const RigidDepthChecker checker(parts, 0.025, 0.01);
  EXPECT_TRUE(checker.IsValid(Pose{}));
  EXPECT_TRUE(checker.IsValid(PoseAt(0, 0, 1.0)));  // out past the rim: the clip bends in the plate
  // Down 1 mm: the beam 0.8 mm and the hook 0.7 mm into the bracket, the
  // panel on the plate.
  EXPECT_FALSE(checker.IsValid(PoseAt(0, 0, -1.0)));
  const DepthReport down = checker.Measure(PoseAt(0, 0, -1.0));
  EXPECT_EQ(down.rigid_shell, 1);
  EXPECT_EQ(down.rigid_static_shell, 4);
  EXPECT_NEAR(down.rigid_depth, 0.8, 1e-9);
}

// A solid peg 10 x 10 x 20 in a hole between two walls 2 thick (x >= 5 and
// x <= -5.5), pressed `pressed` into the first; classified at the
// tolerance 0.05. Static shell 0 is the wall it is pressed into.
std::shared_ptr<const PartModel> PegPressedIntoAWall(double pressed) {
  const TriangleMesh peg = MakeBox({-5, -5, -10}, {5 + pressed, 5, 10});
  TriangleMesh plate = MakeBox({5, -20, -2}, {20, 20, 0});
  plate.Append(MakeBox({-20, -20, -2}, {-5.5, 20, 0}));
  return ClassifyParts(peg, plate, Pose{}, 0.05);
}

TEST(RigidDepth, ASolidBlockPressedLightlyIntoAWallIsAFit) {
  // A solid peg pressed 0.3 mm into a hole's wall: the peg is the anchor,
  // and the overlap a layer of 0.3 x 10 x 2 mm (area 20 >= 100 x 0.3^2,
  // 0.3 <= 5% of the peg's 24 mm diagonal): a fit interference. The peg
  // may be drawn out along it, never pushed deeper.
  const auto parts = PegPressedIntoAWall(0.3);
  EXPECT_EQ(parts->FastenerCount(), 0);
  EXPECT_TRUE(parts->rigid_interference.empty());
  ASSERT_EQ(parts->fits.size(), 1u);
  EXPECT_EQ(parts->fits[0].robot_shell, 0);
  EXPECT_EQ(parts->fits[0].static_shell, 0);
  EXPECT_NEAR(parts->fits[0].installed_depth, 0.3, 0.005 + 1e-12);
  EXPECT_NEAR(parts->fits[0].area, 20, 6);  // of sub-triangles whose centres are deep: approximate
  const RigidDepthChecker checker(parts, 0.05, 0.01);
  EXPECT_TRUE(checker.IsValid(Pose{}));
  EXPECT_TRUE(checker.IsValid(PoseAt(0, 0, 5)));     // drawn along the fit
  EXPECT_TRUE(checker.IsValid(PoseAt(-0.2, 0, 0)));  // released a little
  EXPECT_FALSE(checker.IsValid(PoseAt(0.1, 0, 0)));  // pushed 0.1 deeper
  EXPECT_NEAR(checker.Measure(PoseAt(0.1, 0, 0)).rigid_depth, 0.1, 0.005 + 1e-12);
  EXPECT_NEAR(checker.Measure(PoseAt(0.1, 0, 0)).fit_depth, 0.4, 1e-12);
}

// Pressed 0.03 mm into the wall: within the tolerance (0.05), no fit. The
// planners check at half the tolerance (0.025), where the installed pose
// itself would be invalid ("start pose is in collision", an internal error
// on a press fit of a few hundredths): the pair may stay as deep as it was
// installed plus half the checker's limit, so the planner's allowance
// (0.0425) plus its step floor never exceeds the final check's (0.055).
TEST(RigidDepth, APegPressedInWithinTheToleranceMayStayThatDeep) {
  const auto parts = PegPressedIntoAWall(0.03);
  EXPECT_EQ(parts->FastenerCount(), 0);
  EXPECT_TRUE(parts->rigid_interference.empty());
  EXPECT_TRUE(parts->fits.empty());
  EXPECT_NEAR(parts->OverlapDepth(0, 0), 0.03, 1e-9);
  EXPECT_EQ(parts->OverlapDepth(0, 1), 0);  // 0.5 mm from the other wall
  const RigidDepthChecker planning(parts, 0.025, 0.0125);
  EXPECT_TRUE(planning.IsValid(Pose{}));
  EXPECT_TRUE(planning.IsValid(PoseAt(0, 0, 5)));       // drawn out along the wall
  EXPECT_TRUE(planning.IsValid(PoseAt(0.01, 0, 0)));    // 0.04 deep
  EXPECT_FALSE(planning.IsValid(PoseAt(0.015, 0, 0)));  // 0.045
  const RigidDepthChecker final_check(parts, 0.05, 0.0125);
  EXPECT_TRUE(final_check.IsValid(PoseAt(0.02, 0, 0)));   // 0.05
  EXPECT_FALSE(final_check.IsValid(PoseAt(0.03, 0, 0)));  // 0.06
  // The other wall keeps the plain limit.
  EXPECT_TRUE(planning.IsValid(PoseAt(-0.47, 0, 0)));   // 0.03 from it
  EXPECT_FALSE(planning.IsValid(PoseAt(-0.53, 0, 0)));  // 0.03 into it
}

TEST(RigidDepth, ASolidBlockDeepInAWallClashes) {
  // 3 mm into the wall: more than 5% of the peg's size: a clash.
  const TriangleMesh peg = MakeBox({-5, -5, -10}, {8, 5, 10});
  TriangleMesh plate = MakeBox({5, -20, -2}, {20, 20, 0});
  plate.Append(MakeBox({-20, -20, -2}, {-5.5, 20, 0}));
  const auto parts = ClassifyParts(peg, plate, Pose{}, 0.05);
  EXPECT_TRUE(parts->fits.empty());
  ASSERT_EQ(parts->rigid_interference.size(), 1u);
  EXPECT_EQ(parts->rigid_interference[0], 0);
  // The scene key fit_interference (FitRule::max_depth) decides alone.
  FitRule rule;
  rule.max_depth = 3.5;
  EXPECT_TRUE(
      ClassifyParts(peg, plate, Pose{}, 0.05, UnmeasuredInterference::kRigid, rule)->rigid_interference.empty());
  rule.max_depth = 0;
  const TriangleMesh light = MakeBox({-5, -5, -10}, {5.3, 5, 10});
  EXPECT_EQ(ClassifyParts(light, plate, Pose{}, 0.05, UnmeasuredInterference::kRigid, rule)->rigid_interference.size(),
            1u);
}

TEST(RigidDepth, ACapOnAPostOverlappingLiftsOffButCannotBeTurnedIntoIt) {
  // A cap (bore 4, non-convex) on a post of radius 4.3: 0.3 mm of overlap
  // all round the bore, as a CAD export of a press fit has.
  const TriangleMesh cap = MakeSolidOfRevolution({{0, 8}, {4, 8}, {4, 0}, {6, 0}, {6, 10}, {0, 10}}, 64);
  const TriangleMesh post = MakeSolidOfRevolution({{0, -5}, {4.3, -5}, {4.3, 7}, {0, 7}}, 64);
  const auto parts = ClassifyParts(cap, post, Pose{}, 0.05);
  EXPECT_TRUE(parts->rigid_interference.empty());
  ASSERT_EQ(parts->fits.size(), 1u);
  EXPECT_NEAR(parts->fits[0].installed_depth, 0.3, 0.01);
  EXPECT_GT(std::abs(parts->fits[0].release.z()), 0.99);  // it slides out along the post's axis
  const RigidDepthChecker checker(parts, 0.05, 0.01);
  for (double z : {0.0, 2.0, 5.0, 8.0, 12.0}) EXPECT_TRUE(checker.IsValid(PoseAt(0, 0, z))) << z;
  EXPECT_FALSE(checker.IsValid(PoseAt(0.2, 0, 0)));  // sideways: 0.2 deeper on one side
  Pose tilted;
  tilted.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(checker.IsValid(tilted));
}

// Ridges interlocked: a ring whose inner ridges overlap a post's outer
// ridges by 0.3 mm at their crests (45-degree flanks). The overlap is thin
// and wide enough for a fit by size, but no direction slides it out: every
// flank is 45 degrees across the axis (FitRule::kMaxAcrossRelease), so it is
// a clash, as a nut's thread on a bolt is. A pin pressed into its bore (the
// cap above) has its overlap all along the axis and stays a fit.
TEST(RigidDepth, InterlockedRidgesAreAClashNotAFit) {
  std::vector<Eigen::Vector2d> post = {{0, -1}, {4.0, -1}}, ring = {{7, -0.5}, {7, 5.5}};
  for (int k = 0; k < 5; ++k) {
    post.push_back({4.0, k + 0.0});
    post.push_back({4.5, k + 0.5});
  }
  post.push_back({4.0, 5.0});
  post.push_back({4.0, 6.0});
  post.push_back({0, 6.0});
  ring.push_back({4.8, 5.5});
  for (int k = 5; k > 0; --k) {
    ring.push_back({4.8, k + 0.0});
    ring.push_back({4.2, k - 0.5});
  }
  ring.push_back({4.8, 0.0});
  ring.push_back({4.8, -0.5});
  const TriangleMesh ring_mesh = MakeSolidOfRevolution(ring, 96), post_mesh = MakeSolidOfRevolution(post, 96);
  const auto parts = ClassifyParts(ring_mesh, post_mesh, Pose{}, 0.05);
  EXPECT_TRUE(parts->fits.empty());
  ASSERT_EQ(parts->rigid_interference.size(), 1u);
  EXPECT_GT(parts->installed_depth[0], 0.05);
  // A tessellation whose chord error is known (scene key
  // tessellation_deflection, FitRule::tessellation_depth): an overlap no
  // deeper than it is a fit whatever its shape (surfaces touching in CAD);
  // a deeper one goes by the rule above.
  // The overlap is 0.3 mm across the crests, 0.21 mm deep along the flanks'
  // normals (the depth measured).
  FitRule rule;
  rule.tessellation_depth = 0.25;
  const auto coarse = ClassifyParts(ring_mesh, post_mesh, Pose{}, 0.05, UnmeasuredInterference::kRigid, rule);
  EXPECT_TRUE(coarse->rigid_interference.empty());
  ASSERT_EQ(coarse->fits.size(), 1u);
  const RigidDepthChecker checker(coarse, 0.05, 0.01);
  EXPECT_TRUE(checker.IsValid(Pose{}));
  EXPECT_FALSE(checker.IsValid(PoseAt(0.2, 0, 0)));  // sideways: deeper on one side
  rule.tessellation_depth = 0.15;
  EXPECT_EQ(ClassifyParts(ring_mesh, post_mesh, Pose{}, 0.05, UnmeasuredInterference::kRigid, rule)
                ->rigid_interference.size(),
            1u);
}

TEST(RigidDepth, ANonConvexShellInterferingIsMeasured) {
  // A panel with a dented (non-convex) lug through S at the installed pose:
  // its depth is measured (the surface depth), so it is a fastener like a
  // convex clip.
  TriangleMesh robot = MakeBox({-20, -20, 0}, {20, 20, 2});
  testing::AppendDentedLug(&robot);
  const TriangleMesh plate = MakeBox({-30, -30, -3}, {30, 30, -1});
  const auto parts = ClassifyParts(robot, plate, Pose{}, 0.05);
  ASSERT_EQ(parts->robot_shells.size(), 2u);
  EXPECT_FALSE(parts->robot_shells[1].convex);
  EXPECT_TRUE(std::isfinite(parts->installed_depth[1]));
  EXPECT_GT(parts->installed_depth[1], 0.05);
  EXPECT_EQ(parts->FastenerCount(), 1);
  EXPECT_TRUE(parts->rigid_interference.empty());
}

// A lead in its hole, as KiCad models them: its wall lies 0.0478 mm inside
// the hole's (two 32-gons 0.048 mm apart at their corners, faces parallel),
// within the tolerance of 0.05. The surface depth is an upper bound within
// a tenth of the tolerance, so it may first come out above 0.05; such a
// pair is decided, and the lead is no fastener: the part is a rigid one
// (ChooseValidity gives it to rigid-exact, not the volume model).
TEST(RigidDepth, ALeadWithinTheToleranceOfItsHoleIsNoFastener) {
  TriangleMesh robot = MakeBox({20, 20, 5}, {60, 60, 20});  // the body: the anchor
  const double r = 5.048;                                   // the hole's 5, and the overlap
  // A headed lead: non-convex, as are the plate's hole walls.
  const TriangleMesh lead = MakeSolidOfRevolution({{0, -3}, {r, -3}, {r, 3}, {7, 3}, {7, 4}, {0, 4}}, 32);
  robot.Append(lead);
  const TriangleMesh plate = MakeSolidOfRevolution({{5, -2}, {15, -2}, {15, 2}, {5, 2}}, 32);
  const auto parts = ClassifyParts(robot, plate, Pose{}, 0.05);
  ASSERT_EQ(parts->robot_shells.size(), 2u);
  const int lead_shell = parts->anchor == 0 ? 1 : 0;
  EXPECT_FALSE(parts->robot_shells[lead_shell].convex);
  EXPECT_GT(parts->installed_depth[lead_shell], 0.047);
  EXPECT_LE(parts->installed_depth[lead_shell], 0.05);
  EXPECT_EQ(parts->FastenerCount(), 0);
  EXPECT_TRUE(parts->non_convex_interference.empty());
  EXPECT_TRUE(parts->rigid_interference.empty());
}

TEST(RigidDepth, RotatedAndMovedSceneGivesTheSameClassificationAndDepths) {
  const KeyScene scene;
  Eigen::Isometry3d world = Eigen::Isometry3d::Identity();
  world.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  world.translation() = Eigen::Vector3d(2500, -1300, 3100);
  TriangleMesh robot = scene.robot, environment = scene.environment;
  for (auto& v : robot.vertices) v = world * v;
  for (auto& v : environment.vertices) v = world * v;
  const auto parts = ClassifyParts(robot, environment, Pose{}, 0.05);
  const RigidDepthChecker checker(parts, 0.05, 0.01);
  EXPECT_NEAR(checker.Measure(Pose{}).rigid_depth, -0.5, 1e-9);
  // The same sideways cut, in world coordinates: a world translation of the
  // local x axis moves D about the world origin.
  Pose cut;
  cut.t = world.linear() * Eigen::Vector3d(1.0, 0, 0);
  EXPECT_NEAR(checker.Measure(cut).rigid_depth, 0.5, 1e-9);
}

}  // namespace
}  // namespace ausbau
