// The depth over a translation (collision/mesh_depth.h
// MeasureSweptSurfaceDepth and SweptSurfacesMayMeet; geometry/shells.h
// ConvexSweptDepthBound) against depths computed by hand and against the
// static depth sampled densely along the motion: where the swept bound
// says "no deeper than d", no sampled pose is deeper.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collision/mesh_depth.h"
#include "geometry/primitives.h"
#include "geometry/shells.h"

namespace ausbau {
namespace {

Shell OneShell(const TriangleMesh& mesh) {
  auto shells = SplitIntoShells(mesh);
  EXPECT_EQ(shells.size(), 1u);
  return shells.front();
}

TriangleMesh TurnedAboutZ(TriangleMesh mesh, double angle) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (auto& v : mesh.vertices) v = r * v;
  return mesh;
}

// A block 5 high with a bore of radius 4, and a pin of radius 4 from z = -5
// to 7 through it, both 32-gons; `phase` turns the pin by that share of a
// segment.
TriangleMesh Block() { return MakeSolidOfRevolution({{4, 0}, {8, 0}, {8, 5}, {4, 5}}, 32); }
TriangleMesh Pin(double phase) {
  return TurnedAboutZ(MakeSolidOfRevolution({{0, -5}, {4, -5}, {4, 7}, {0, 7}}, 32), phase * 2 * M_PI / 32);
}

SurfaceDepth Swept(const DepthSurface& a, const Eigen::Isometry3d& pose, const Eigen::Vector3d& move,
                   const DepthSurface& b, double decide, double resolution) {
  SurfaceDepthOptions options;
  options.resolution = resolution;
  options.decide = decide;
  return MeasureSweptSurfaceDepth(a, pose, move, b, options, 1 << 20);
}

TEST(SweptDepth, APinDrawnOutOfItsBoreIsProvedInOneQuery) {
  // In phase the facets coincide (depth 0); half a segment out of phase
  // each polygon's corners stand 4 (1 - cos(pi / 32)) = 0.0193 into the
  // other all along the bore. Either way the pin slides out along z no
  // deeper, and the whole pull is proved at once with few prisms (before
  // the swept bounds, a pose per hundredth of a mm of a surface-depth
  // search each).
  const DepthSurface block(OneShell(Block()));
  const double chord = 4 * (1 - std::cos(M_PI / 32));
  for (double phase : {0.0, 0.5}) {
    const DepthSurface pin(OneShell(Pin(phase)));
    for (double length : {0.02, 0.5, 5.0, 20.0}) {
      const SurfaceDepth d = Swept(pin, Eigen::Isometry3d::Identity(), {0, 0, length}, block, 0.025, 0.0025);
      EXPECT_LE(d.upper, 0.025) << "phase " << phase << " length " << length;
      EXPECT_LE(d.lower, chord + 1e-9);
      EXPECT_LT(d.sub_triangles, 20000) << "phase " << phase << " length " << length;
    }
  }
}

TEST(SweptDepth, APullThatDrivesThePinIntoTheWallIsNotProved) {
  // The same pin drawn out along a direction 2 degrees off the bore's axis:
  // after 5 mm it is 0.17 mm into the wall. Not proved, and the depth found
  // on the way exceeds what is allowed.
  const DepthSurface block(OneShell(Block())), pin(OneShell(Pin(0.0)));
  const Eigen::Vector3d tilted(std::sin(2 * M_PI / 180), 0, std::cos(2 * M_PI / 180));
  const SurfaceDepth d = Swept(pin, Eigen::Isometry3d::Identity(), 5 * tilted, block, 0.025, 0.0025);
  EXPECT_GT(d.upper, 0.025);
  EXPECT_GT(d.lower, 0.025);
  // Drawn sideways 1 mm it is 1 mm deep.
  const SurfaceDepth sideways = Swept(pin, Eigen::Isometry3d::Identity(), {1, 0, 0}, block, 0.5, 0.0025);
  EXPECT_GT(sideways.lower, 0.5);
}

TEST(SweptDepth, TheSweptBoundNeverFallsBelowADepthOnTheWay) {
  // A cap on a post and an L in a U, moved along random short translations
  // about contact: where the swept search proves "no deeper than `decide`",
  // no pose sampled along the motion (every 1/20 of it) has a surface
  // attained deeper (the static search's lower bound: a depth found).
  const TriangleMesh cap = MakeSolidOfRevolution({{0, 8}, {4, 8}, {4, 0}, {6, 0}, {6, 10}, {0, 10}}, 24);
  const TriangleMesh post = MakeSolidOfRevolution({{0, -5}, {4.02, -5}, {4.02, 7}, {0, 7}}, 24);
  const TriangleMesh u = MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5);
  const TriangleMesh l = MakePrism({{2.1, 2.1}, {7.9, 2.1}, {7.9, 3}, {3, 3}, {3, 9}, {2.1, 9}}, 1, 4);
  struct Pair {
    TriangleMesh a, b;
  };
  const Pair pairs[2] = {{cap, post}, {l, u}};
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  int proved = 0, not_proved = 0;
  for (const Pair& pair : pairs) {
    const DepthSurface a(OneShell(pair.a)), b(OneShell(pair.b));
    for (int trial = 0; trial < 30; ++trial) {
      const Eigen::Isometry3d pose(
          Eigen::Translation3d(0.03 * Eigen::Vector3d(unit(random), unit(random), unit(random))));
      // Mostly along z (the cap lifts off, the L slides out of the U's
      // channel) a little askew; now and then anywhere.
      const Eigen::Vector3d askew(0.02 * unit(random), 0.02 * unit(random), unit(random) > 0 ? 1 : -1);
      const Eigen::Vector3d anywhere(unit(random), unit(random), unit(random));
      const Eigen::Vector3d move = (0.5 + 2 * (unit(random) + 1)) * (trial % 3 == 0 ? anywhere : askew);
      const double decide = 0.02 + 0.1 * (unit(random) + 1);
      const SurfaceDepth swept = Swept(a, pose, move, b, decide, decide / 10);
      double deepest = 0;
      for (int k = 0; k <= 20; ++k) {
        SurfaceDepthOptions options;
        options.resolution = decide / 20;
        const Eigen::Isometry3d at = Eigen::Translation3d(move * (k / 20.0)) * pose;
        deepest = std::max(deepest, MeasureSurfaceDepth(a, at, b, options).lower);
      }
      if (swept.upper <= decide) {
        ++proved;
        EXPECT_LE(deepest, decide) << "trial " << trial;
      } else {
        ++not_proved;
      }
    }
  }
  // Both answers were given.
  EXPECT_GT(proved, 10);
  EXPECT_GT(not_proved, 10);
}

TEST(SweptDepth, SurfacesThatPassEachOtherDoNotMeet) {
  // A 1 mm cube passing 0.1 above a plate's face, and through the plate.
  const TriangleMesh plate = MakeBox({-10, -10, -1}, {10, 10, 0});
  const Shell cube = OneShell(MakeBox({0, 0, 0}, {1, 1, 1}));
  const DepthSurface surface(OneShell(plate));
  const Eigen::Isometry3d above(Eigen::Translation3d(-5, 0, 0.1));
  EXPECT_FALSE(SweptSurfacesMayMeet(cube.vertices, cube.triangles, above, {10, 0, 0}, surface, 0.0));
  EXPECT_TRUE(SweptSurfacesMayMeet(cube.vertices, cube.triangles, above, {10, 0, -0.2}, surface, 0.0));
  EXPECT_TRUE(SweptSurfacesMayMeet(cube.vertices, cube.triangles, above, {10, 0, 0}, surface, 0.2));
}

TEST(SweptDepth, ConvexSweptDepthOfABoxSlidingOnABox) {
  // A box pressed 0.01 into another's top face and slid along it: the depth
  // stays 0.01, and the bound says so exactly (the face normal's overlap
  // does not change). Slid down into it, the bound is the deepest depth on
  // the way; and never below any depth sampled on the way.
  const Shell base = OneShell(MakeBox({-10, -10, -1}, {10, 10, 0}));
  const Shell box = OneShell(MakeBox({0, 0, -0.01}, {1, 1, 1}));
  const Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  EXPECT_NEAR(ConvexSweptDepthBound(box, at, {5, 3, 0}, base), 0.01, 1e-12);
  EXPECT_NEAR(ConvexSweptDepthBound(box, at, {0, 0, -0.3}, base), 0.31, 1e-12);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Isometry3d pose =
        Eigen::Translation3d(Eigen::Vector3d(8 * unit(random), 8 * unit(random), 0.5 * unit(random))) *
        Eigen::AngleAxisd(unit(random), Eigen::Vector3d(unit(random), unit(random), unit(random)).normalized());
    const Eigen::Vector3d move(2 * unit(random), 2 * unit(random), unit(random));
    const double bound = ConvexSweptDepthBound(box, pose, move, base);
    for (int k = 0; k <= 50; ++k) {
      const Eigen::Isometry3d along = Eigen::Translation3d(move * (k / 50.0)) * pose;
      EXPECT_LE(ConvexSignedDepth(box, along, base), bound + 1e-12) << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace ausbau
