// The surface depth of non-convex and open shells (collision/mesh_depth.h)
// against depths computed by hand: an L in a U, a cap on a post, a ring on
// a shaft, a block with a hole (closed, and with boundary edges).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <utility>

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

SurfaceDepth Measure(const TriangleMesh& a, const TriangleMesh& b, double resolution = 1e-3) {
  const DepthSurface sa(OneShell(a)), sb(OneShell(b));
  SurfaceDepthOptions options;
  options.resolution = resolution;
  return MeasureSurfaceDepth(sa, Eigen::Isometry3d::Identity(), sb, options);
}

// Every triangle split into four at its edges' midpoints (shared between
// neighbours, so the shell stays closed).
TriangleMesh Subdivided(const TriangleMesh& mesh) {
  TriangleMesh out;
  out.vertices = mesh.vertices;
  std::map<std::pair<int, int>, int> midpoint;
  auto mid = [&](int a, int b) {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    auto it = midpoint.find(key);
    if (it != midpoint.end()) return it->second;
    out.vertices.push_back(0.5 * (mesh.vertices[a] + mesh.vertices[b]));
    return midpoint[key] = static_cast<int>(out.vertices.size()) - 1;
  };
  for (const auto& t : mesh.triangles) {
    const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
    out.triangles.push_back({t[0], ab, ca});
    out.triangles.push_back({ab, t[1], bc});
    out.triangles.push_back({ca, bc, t[2]});
    out.triangles.push_back({ab, bc, ca});
  }
  return out;
}

// A cap (bore radius 4, outer radius 6, 10 high, roof 2 thick) of n segments.
TriangleMesh Cap(int n) { return MakeSolidOfRevolution({{0, 8}, {4, 8}, {4, 0}, {6, 0}, {6, 10}, {0, 10}}, n); }
TriangleMesh Post(double radius, int n) {
  return MakeSolidOfRevolution({{0, -5}, {radius, -5}, {radius, 7}, {0, 7}}, n);
}

TEST(MeshDepth, PrimitivesAreClosedAndOriented) {
  EXPECT_TRUE(DepthSurface(OneShell(Post(4, 48))).oriented());
  for (const TriangleMesh& mesh :
       {Cap(64), MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5)}) {
    const Shell shell = OneShell(mesh);
    EXPECT_TRUE(shell.closed);
    EXPECT_FALSE(shell.convex);
    EXPECT_TRUE(DepthSurface(shell).oriented());
  }
  // The U's area is 10 x 10 - 6 x 8 = 52, times 5 high.
  EXPECT_NEAR(OneShell(MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5)).volume,
              260, 1e-9);
}

TEST(MeshDepth, SignedDistanceOfACap) {
  const DepthSurface cap(OneShell(Cap(64)));
  // In the wall, 0.5 from the bore and 1.5 from the outside; in the bore
  // (outside the solid) 1 from the wall; in the roof 1 from both faces.
  EXPECT_NEAR(cap.SignedDistance({4.5, 0, 5}), 0.5, 0.01);
  EXPECT_NEAR(cap.SignedDistance({0, 3, 4}), -1, 0.01);
  EXPECT_NEAR(cap.SignedDistance({0, 0, 9}), 1, 1e-9);
  EXPECT_NEAR(cap.SignedDistance({0, 0, 12}), -2, 1e-9);
}

TEST(MeshDepth, ConvexBoxesAgreeWithTheSeparatingAxisDepth) {
  const TriangleMesh a = MakeBox({0, 0, 0}, {1, 1, 1});
  const TriangleMesh b = MakeBox({0.9, 0.2, 0.3}, {2, 0.8, 0.7});
  const SurfaceDepth depth = Measure(a, b);
  const double sat = ConvexSignedDepth(OneShell(a), Eigen::Isometry3d::Identity(), OneShell(b));
  EXPECT_NEAR(sat, 0.1, 1e-12);
  EXPECT_GE(depth.upper, 0.1 - 1e-12);
  EXPECT_LE(depth.upper, 0.1 + 1e-3 + 1e-12);
  EXPECT_NEAR(depth.lower, 0.1, 1e-3);
}

TEST(MeshDepth, SeparatedAndTouchingShellsAreNotDeep) {
  EXPECT_EQ(Measure(Cap(32), Post(3.5, 32)).upper, 0);  // 0.5 radial clearance, post top 1 below the roof
  const SurfaceDepth touching = Measure(MakeBox({0, 0, 0}, {1, 1, 1}), MakeBox({1, 0.2, 0.2}, {2, 0.8, 0.8}));
  EXPECT_LE(touching.upper, 1e-3);
}

TEST(MeshDepth, CapOnAPostOverlappingByAThirdOfAMillimetre) {
  // Post radius 4.3 in a bore of radius 4: the faces of a 64-gon lie at
  // r cos(pi / 64), so the radial overlap is 4.3 - 4 cos(pi / 64) at most
  // (corner of the post against a face of the bore) and at least
  // 4.3 cos(pi / 64) - 4 (face against face).
  const double c = std::cos(M_PI / 64);
  const SurfaceDepth depth = Measure(Cap(64), Post(4.3, 64), 1e-3);
  EXPECT_GE(depth.upper, 4.3 * c - 4 - 1e-9);
  EXPECT_LE(depth.upper, 4.3 - 4 * c + 1e-3);
  EXPECT_GE(depth.upper - depth.lower, 0);
  EXPECT_LE(depth.upper - depth.lower, 1e-3 + 1e-12);
}

TEST(MeshDepth, RingOnAShaft) {
  const TriangleMesh ring = MakeSolidOfRevolution({{5, 0}, {7, 0}, {7, 2}, {5, 2}}, 96);
  const TriangleMesh shaft = MakeSolidOfRevolution({{0, -10}, {5.2, -10}, {5.2, 10}, {0, 10}}, 96);
  const double c = std::cos(M_PI / 96);
  const SurfaceDepth depth = Measure(ring, shaft);
  EXPECT_GE(depth.upper, 5.2 * c - 5 - 1e-9);
  EXPECT_LE(depth.upper, 5.2 - 5 * c + 1e-3);
  // Moved by the pose: the ring 0.1 off centre overlaps 0.1 more on one side.
  const DepthSurface sr(OneShell(ring)), ss(OneShell(shaft));
  SurfaceDepthOptions options;
  options.resolution = 1e-3;
  const SurfaceDepth off = MeasureSurfaceDepth(sr, Eigen::Isometry3d(Eigen::Translation3d(0.1, 0, 3)), ss, options);
  EXPECT_GE(off.upper, 5.3 * c - 5 - 1e-9);
  EXPECT_LE(off.upper, 5.3 - 5 * c + 1e-3);
}

TEST(MeshDepth, LFootInTheWallOfAU) {
  const TriangleMesh u = MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5);
  // The foot of the L reaches x = 8.4: 0.4 into the wall at x = 8 .. 10.
  const TriangleMesh l = MakePrism({{3, 3}, {8.4, 3}, {8.4, 4}, {4, 4}, {4, 12}, {3, 12}}, 1, 4);
  const SurfaceDepth depth = Measure(l, u);
  EXPECT_NEAR(depth.upper, 0.4, 1e-3 + 1e-12);
  EXPECT_NEAR(depth.lower, 0.4, 1e-3 + 1e-12);
  // A yes/no question stops as soon as it is answered.
  const DepthSurface sl(OneShell(l)), su(OneShell(u));
  SurfaceDepthOptions decide;
  decide.decide = 0.3;
  EXPECT_GT(MeasureSurfaceDepth(sl, Eigen::Isometry3d::Identity(), su, decide).lower, 0.3);
  decide.decide = 0.5;
  EXPECT_LE(MeasureSurfaceDepth(sl, Eigen::Isometry3d::Identity(), su, decide).upper, 0.5);
}

// A box standing 5 um into a face of a non-convex shell (a U): its walls
// cross the face along lines. The part of each wall behind the face is at
// most 5 um deep, the part in front crosses nothing: settled whole, not
// refined along the line.
TEST(MeshDepth, AWallAcrossAFaceIsSettledWhole) {
  const TriangleMesh u = MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5);
  const TriangleMesh box = MakeBox({3, -10, 1}, {7, 0.005, 4});
  const SurfaceDepth depth = Measure(box, u);
  EXPECT_GE(depth.upper, 0.005 - 1e-12);
  EXPECT_LE(depth.upper, 0.005 + 1e-3);
  EXPECT_NEAR(depth.lower, 0.005, 1e-3);
  // The four walls' triangles and the face in the U; without the bound the
  // walls are refined to the resolution along 14 mm of crossing (thousands).
  EXPECT_LT(depth.sub_triangles, 200);
}

TEST(MeshDepth, StraddleBoundHoldsOnlyWherePointsInFrontAreOutside) {
  const DepthSurface u(
      OneShell(MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5)));
  int outer = -1, inner = -1;
  u.SignedDistance({5, 0, 2.5}, &outer);  // the outer face y = 0 (normal -y)
  u.SignedDistance({5, 2, 2.5}, &inner);  // the channel's floor y = 2 (normal +y)
  ASSERT_GE(outer, 0);
  ASSERT_GE(inner, 0);
  const double gap = 1e-6;
  // Across the outer face, 0.1 behind it at most: the bound is that depth.
  EXPECT_NEAR(
      u.StraddleBound({Eigen::Vector3d(4, 0.1, 2.5), Eigen::Vector3d(6, 0.05, 2.5), Eigen::Vector3d(5, -3, 2.5)}, outer,
                      gap),
      0.1, 1e-9);
  // Across the channel's floor, but the part in front reaches into the
  // right arm (x 8..10), a point 1 deep: no bound from the floor.
  EXPECT_EQ(u.StraddleBound({Eigen::Vector3d(5, 1.995, 2.5), Eigen::Vector3d(9, 6, 2.5), Eigen::Vector3d(5, 6, 2.5)},
                            inner, gap),
            std::numeric_limits<double>::infinity());
  // The same floor, the part in front in the channel only: 5 um.
  EXPECT_NEAR(u.StraddleBound({Eigen::Vector3d(5, 1.995, 2.5), Eigen::Vector3d(7, 6, 2.5), Eigen::Vector3d(5, 6, 2.5)},
                              inner, gap),
              0.005, 1e-9);
  // Its cut with the plane beside the face (x 11..12): no bound.
  EXPECT_EQ(
      u.StraddleBound({Eigen::Vector3d(11, 0.1, 2.5), Eigen::Vector3d(12, 0.1, 2.5), Eigen::Vector3d(11.5, -3, 2.5)},
                      outer, gap),
      std::numeric_limits<double>::infinity());
  // Wholly on one side: nothing to cut.
  EXPECT_EQ(u.StraddleBound({Eigen::Vector3d(4, 0.1, 2.5), Eigen::Vector3d(6, 0.1, 2.5), Eigen::Vector3d(5, 0.2, 2.5)},
                            outer, gap),
            std::numeric_limits<double>::infinity());
}

// The U's top face is one flat region that is not convex (no convex patch):
// a box lying 5 um into its bottom band is still settled whole; a triangle
// whose shadow reaches over the channel gets no bound from it; a triangle
// whose part in front meets the other jaw of a C gets none either.
TEST(MeshDepth, AFlatFaceOfAnyOutlineBoundsWhatLiesUnderIt) {
  const TriangleMesh u = MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5);
  const SurfaceDepth depth = Measure(MakeBox({1, 0.5, 4.995}, {9, 1.5, 8}), u);
  EXPECT_GE(depth.upper, 0.005 - 1e-12);
  EXPECT_LE(depth.upper, 0.005 + 1e-3);
  EXPECT_LT(depth.sub_triangles, 200);

  const DepthSurface su(OneShell(u));
  int top = -1;
  su.SignedDistance({5, 1, 5}, &top);
  ASSERT_GE(top, 0);
  const double gap = 1e-6;
  using V = Eigen::Vector3d;
  EXPECT_NEAR(su.FaceRegionBound({V(1, 0.5, 4.995), V(9, 0.5, 4.99), V(5, 1.5, 5.5)}, top, gap), 0.01, 1e-6);
  EXPECT_NEAR(su.FaceRegionBound({V(1, 0.5, 4.995), V(9, 0.5, 4.99), V(5, 1.5, 4.98)}, top, gap), 0.02, 1e-6);
  const double none = std::numeric_limits<double>::infinity();
  EXPECT_EQ(su.FaceRegionBound({V(1, 0.5, 4.995), V(9, 0.5, 4.99), V(5, 4, 5.5)}, top, gap), none);  // over the channel
  EXPECT_EQ(su.FaceRegionBound({V(1, 0.5, 4.995), V(9, 0.5, 4.99), V(5, 1.5, 4.98)}, top, gap, 0.015), none);

  const DepthSurface c(OneShell(MakePrism({{0, 0}, {10, 0}, {10, 1}, {2, 1}, {2, 3}, {10, 3}, {10, 4}, {0, 4}}, 0, 5)));
  int jaw = -1;
  c.SignedDistance({6, 1, 2.5}, &jaw);  // the lower jaw's face y = 1, under the upper jaw (y 3..4)
  ASSERT_GE(jaw, 0);
  EXPECT_EQ(c.FaceRegionBound({V(4, 0.995, 2.5), V(8, 0.995, 2.5), V(6, 3.5, 2.5)}, jaw, gap), none);
  EXPECT_NEAR(c.FaceRegionBound({V(4, 0.995, 2.5), V(8, 0.995, 2.5), V(6, 2.5, 2.5)}, jaw, gap), 0.005, 1e-6);
}

// Both face bounds against the depth itself: a U whose corners are moved
// off their faces by up to 3e-5 (a CAD face written in float32 far from the
// origin is flat to about that), and triangles across and under its faces
// at random; wherever a bound is given, no point of the triangle inside
// the U is deeper (SignedDistance at a grid of points on it).
// The deepest of a grid of points on t (25 per edge) inside s: what a
// bound on t must not fall below.
double DeepestSample(const DepthSurface& s, const std::array<Eigen::Vector3d, 3>& t) {
  double deepest = 0;
  constexpr int kGrid = 24;
  for (int i = 0; i <= kGrid; ++i)
    for (int j = 0; i + j <= kGrid; ++j) {
      const double a = double(i) / kGrid, b = double(j) / kGrid;
      deepest = std::max(deepest, s.SignedDistance((1 - a - b) * t[0] + a * t[1] + b * t[2]));
    }
  return deepest;
}

TEST(MeshDepth, TheFaceBoundsNeverFallBelowTheDepth) {
  TriangleMesh u = Subdivided(MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5));
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (auto& v : u.vertices) v += 3e-5 * Eigen::Vector3d(unit(random), unit(random), unit(random));
  const DepthSurface s(OneShell(u));
  ASSERT_TRUE(s.oriented());
  const double gap = 1e-4;
  int region_bounds = 0, straddle_bounds = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d centre(10 * (unit(random) + 1) / 2, 10 * (unit(random) + 1) / 2, 5 * (unit(random) + 1) / 2);
    const double size = 0.05 + 2 * (unit(random) + 1);
    std::array<Eigen::Vector3d, 3> t;
    for (auto& corner : t) corner = centre + size * Eigen::Vector3d(unit(random), unit(random), unit(random));
    int face = -1;
    s.SignedDistance(centre, &face);
    const double region = s.FaceRegionBound(t, face, gap);
    const double straddle = s.StraddleBound(t, face, gap);
    if (std::isinf(region) && std::isinf(straddle)) continue;
    region_bounds += !std::isinf(region);
    straddle_bounds += !std::isinf(straddle);
    const double deepest = DeepestSample(s, t);
    EXPECT_LE(deepest, region + 1e-9) << "trial " << trial;
    EXPECT_LE(deepest, straddle + 1e-9) << "trial " << trial;
  }
  // The test tried both (regions form despite the rounding).
  EXPECT_GT(region_bounds, 50);
  EXPECT_GT(straddle_bounds, 0);
}

TEST(MeshDepth, TheShiftOffBoundNeverFallsBelowTheDepth) {
  // Random triangles about the U's surface (as above): wherever the bound
  // moving a triangle off the surface holds, no sampled point of it is
  // deeper than the bound.
  TriangleMesh u = Subdivided(MakePrism({{0, 0}, {10, 0}, {10, 10}, {8, 10}, {8, 2}, {2, 2}, {2, 10}, {0, 10}}, 0, 5));
  const DepthSurface s(OneShell(u));
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  const double gap = 1e-4, shift = 0.05;
  int bounds = 0, by_corners = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d centre(10 * (unit(random) + 1) / 2, 10 * (unit(random) + 1) / 2, 5 * (unit(random) + 1) / 2);
    const double size = 0.01 + 0.5 * (unit(random) + 1);
    std::array<Eigen::Vector3d, 3> t;
    for (auto& corner : t) corner = centre + size * Eigen::Vector3d(unit(random), unit(random), unit(random));
    // Flattened onto the nearest face now and then: contact, the case it is for.
    const TriangleBvh::Nearest nearest = s.bvh().NearestPoint((t[0] + t[1] + t[2]) / 3.0);
    if (trial % 2 == 0) {
      const auto& f = s.triangles()[nearest.triangle];
      const Eigen::Vector3d n =
          (s.vertices()[f[1]] - s.vertices()[f[0]]).cross(s.vertices()[f[2]] - s.vertices()[f[0]]).normalized();
      for (auto& corner : t) corner -= (corner - nearest.point).dot(n) * n;
    }
    // Half of the trials move the triangle along a direction of its own
    // first (as into the shell it belongs to), half of those also halfway
    // between it and the normals at its corners: the bound holds whichever
    // way the move frees it.
    Eigen::Vector3d own = Eigen::Vector3d::Zero();
    if (trial % 4 < 2) own = Eigen::Vector3d(unit(random), unit(random), unit(random)).normalized();
    const bool corners = trial % 8 < 2;
    const TriangleBvh::Nearest at_centre = s.bvh().NearestPoint((t[0] + t[1] + t[2]) / 3.0);
    const double bound = s.ShiftOffBound(t, at_centre, shift, gap, own, corners);
    if (std::isinf(bound)) continue;
    EXPECT_EQ(bound, shift);
    ++bounds;
    if (corners && std::isinf(s.ShiftOffBound(t, at_centre, shift, gap, own, false))) ++by_corners;
    const double deepest = DeepestSample(s, t);
    EXPECT_LE(deepest, bound + 1e-9) << "trial " << trial;
  }
  EXPECT_GT(bounds, 300);  // the bound was tried where it holds
  // Triangles of another shell lying on the U's inner floor (y = 2), up
  // to its inner wall (x = 2), into both by up to 0.01 at random: off the
  // floor (their own shell's inward normal, +y) they still meet the wall,
  // off the wall they still meet the floor; halfway to the normal at the
  // corner on the concave edge they leave both, where no point was deeper
  // than the move.
  for (int trial = 0; trial < 500; ++trial) {
    const double into = 0.01 * (unit(random) + 1) / 2, size = 0.05 + 0.5 * (unit(random) + 1);
    const double z = 1 + 3 * (unit(random) + 1) / 2;
    const std::array<Eigen::Vector3d, 3> t = {Eigen::Vector3d(2 - into, 2 - into, z),
                                              Eigen::Vector3d(2 + size, 2 - into, z - size / 2),
                                              Eigen::Vector3d(2 + size, 2 - into, z + size / 2)};
    const TriangleBvh::Nearest at_centre = s.bvh().NearestPoint((t[0] + t[1] + t[2]) / 3.0);
    const double bound = s.ShiftOffBound(t, at_centre, shift, gap, Eigen::Vector3d::UnitY(), true);
    if (std::isinf(bound)) continue;
    if (std::isinf(s.ShiftOffBound(t, at_centre, shift, gap, Eigen::Vector3d::UnitY(), false))) ++by_corners;
    EXPECT_LE(DeepestSample(s, t), bound + 1e-9) << "trial " << trial;
  }
  EXPECT_GT(by_corners, 100);  // only the move halfway to a corner's normal freed these
}

TEST(MeshDepth, APlateUnderABoltsHeadAroundItsShankIsSettledWithoutRefiningItsRim) {
  // A bolt (shank radius 5, 300 facets; head radius 9) through a plate's
  // bore (radius 5, 256 facets), its head resting on the plate: the shank's
  // polygon reaches past the bore's by up to 3.8e-4. A piece of the plate's
  // face along the rim, moved into the plate, still meets the shank, and
  // moved off the head (the nearest face) still meets the head; moved
  // halfway between the plate's inward normal and the bolt's normal at its
  // corner on the rim, it leaves both. Without that, the face was refined
  // along the rim until each piece was smaller than the depth that does not
  // matter (as1's bolt on its bracket at a fine tessellation: 51,474
  // sub-triangles a check, 9,018 with it).
  const TriangleMesh bolt = MakeSolidOfRevolution({{0, -20}, {5, -20}, {5, 0}, {9, 0}, {9, 6}, {0, 6}}, 300);
  const TriangleMesh plate = MakeSolidOfRevolution({{5, -10}, {30, -10}, {30, 0}, {5, 0}}, 256);
  const DepthSurface sa(OneShell(bolt)), sb(OneShell(plate));
  // A validity check's question (collision/rigid_depth.cpp): deeper than
  // the tolerance of 0.05? Measured to a tenth of it, settled below half.
  SurfaceDepthOptions options;
  options.resolution = 5e-3;
  options.settle = 0.025;
  options.decide = 0.05;
  const int triangles = static_cast<int>(bolt.triangles.size() + plate.triangles.size());
  const SurfaceDepth depth = MeasureSurfaceDepth(sa, Eigen::Isometry3d::Identity(), sb, options);
  EXPECT_LE(depth.upper, 0.05);  // not deeper than the tolerance
  EXPECT_LE(depth.lower, 4e-4);
  // 3,336 of 4,448; without the halfway moves every one, 4,448.
  EXPECT_LT(depth.sub_triangles, 0.8 * triangles);
  // Pressed 0.1 into the plate, the head is too deep, and found so.
  const SurfaceDepth pressed =
      MeasureSurfaceDepth(sa, Eigen::Isometry3d(Eigen::Translation3d(0, 0, -0.1)), sb, options);
  EXPECT_GT(pressed.lower, 0.05);
}

// Two rings 10 long about z, bore radius 5, outer 12, at z -60..-50 and
// 40..50, in `segments` facets: as1's two brackets' bores for its rod.
TriangleMesh TwoRings(int segments) {
  TriangleMesh rings = MakeSolidOfRevolution({{5, -60}, {12, -60}, {12, -50}, {5, -50}}, segments);
  const TriangleMesh second = MakeSolidOfRevolution({{5, 40}, {12, 40}, {12, 50}, {5, 50}}, segments);
  const int offset = static_cast<int>(rings.vertices.size());
  rings.vertices.insert(rings.vertices.end(), second.vertices.begin(), second.vertices.end());
  for (auto t : second.triangles) rings.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return rings;
}

TEST(MeshDepth, ALongRodThroughTwoRingsOfAnotherTessellationIsSettledTriangleByTriangle) {
  // as1's rod at a fine tessellation, by hand: a rod of radius 5 and 200
  // long, 300 facets, through two rings 10 long whose bores have radius 5
  // in 256 facets. Each polygon reaches into the other by at most the
  // sagitta of its facets (5 (1 - cos(pi / 256)) = 3.8e-4). The rod's
  // facets are slivers 200 long: the nearest feature of the rings to the
  // middle of one is a ring's end face, whose normal does not free it, and
  // bisected along its length it took 15,000-110,000 sub-triangles per
  // ring and 0.06-0.3 s a pose. Moved into the rod, each facet leaves the
  // rings at once.
  const TriangleMesh rod = MakeSolidOfRevolution({{0, -100}, {5, -100}, {5, 100}, {0, 100}}, 300);
  const auto ring_shells = SplitIntoShells(TwoRings(256));
  ASSERT_EQ(ring_shells.size(), 2u);
  const DepthSurface sa(OneShell(rod));
  // A validity check's question (collision/rigid_depth.cpp): a tolerance
  // of 0.05, measured to a tenth of it, settled below half of it.
  SurfaceDepthOptions options;
  options.resolution = 5e-3;
  options.settle = 0.025;
  for (const Shell& ring : ring_shells) {
    const DepthSurface sb(ring);
    const int triangles = static_cast<int>(rod.triangles.size() + ring.triangles.size());
    for (const double along : {0.0, 7.3, -33.1}) {
      const SurfaceDepth depth =
          MeasureSurfaceDepth(sa, Eigen::Isometry3d(Eigen::Translation3d(0, 0, along)), sb, options);
      EXPECT_LE(depth.upper, 0.025);
      EXPECT_LE(depth.lower, 4e-4);
      EXPECT_LE(depth.sub_triangles, triangles) << "each triangle once, at " << along;
    }
    // Pushed 0.1 sideways the rod is about 0.1 deep in the ring's wall, and
    // found so.
    const SurfaceDepth pushed =
        MeasureSurfaceDepth(sa, Eigen::Isometry3d(Eigen::Translation3d(0.1, 0, 0)), sb, options);
    EXPECT_GE(pushed.upper, 0.09);
  }
}

TEST(MeshDepth, ARodInBoresOfOtherPolygonsIsMeasuredWithoutRefiningAlongItsLength) {
  // as1's rod at its default tessellation, by hand: a rod of radius 5 and
  // 200 long in 40 facets, through two rings 10 long whose bores have
  // radius 5 in 36 facets. Each polygon's corners stand into the other's
  // facets, 0.015-0.019 deep, along all of the rings' length: deeper than
  // half the resolution, so a move by that much (ShiftOffBound) frees
  // nothing, and a report's measurement refined each facet along every
  // line where the polygons cross (as1's rod: 0.5 s a pose, 2 x 201 poses
  // a report). Moved into its own shell by the resolution above the depth
  // found, each facet leaves the other part whole.
  const TriangleMesh rod = MakeSolidOfRevolution({{0, -100}, {5, -100}, {5, 100}, {0, 100}}, 40);
  const auto ring_shells = SplitIntoShells(TwoRings(36));
  ASSERT_EQ(ring_shells.size(), 2u);
  const DepthSurface sa(OneShell(rod));
  // A report's measurement (collision/rigid_depth.cpp MeasurePairs): a
  // tolerance of 0.05, measured to a tenth of it.
  SurfaceDepthOptions options;
  options.resolution = 5e-3;
  options.settle = 0.025;
  options.coarse_above = 0.05;
  for (const Shell& ring : ring_shells) {
    const DepthSurface sb(ring);
    const int triangles = static_cast<int>(rod.triangles.size() + ring.triangles.size());
    for (const double along : {0.0, 7.3, -33.1}) {
      const Eigen::Isometry3d pose(Eigen::Translation3d(0, 0, along));
      // The depth by hand: the deepest points are the polygons' corners
      // (each one's edge along the axis), the rod's in the ring and the
      // ring's in the rod; sampled along the ring's length.
      double depth = 0;
      for (double z = ring.box.min.z() + 0.25; z < ring.box.max.z(); z += 0.5) {
        for (int k = 0; k < 40; ++k) {
          const double angle = 2 * M_PI * k / 40;
          depth = std::max(depth, sb.SignedDistance({5 * std::cos(angle), 5 * std::sin(angle), z}));
        }
        for (int k = 0; k < 36; ++k) {
          const double angle = 2 * M_PI * k / 36;
          depth = std::max(depth, sa.SignedDistance({5 * std::cos(angle), 5 * std::sin(angle), z - along}));
        }
      }
      ASSERT_GT(depth, 0.015);
      ASSERT_LT(depth, 0.02);
      const SurfaceDepth measured = MeasureSurfaceDepth(sa, pose, sb, options);
      EXPECT_GE(measured.upper, depth - 1e-9) << "at " << along;
      EXPECT_LE(measured.upper, depth + options.resolution) << "at " << along;
      EXPECT_LE(measured.sub_triangles, 4 * triangles) << "at " << along;
    }
  }
}

TEST(MeshDepth, APinLyingOnItsBoresFacetsIsSettledWhole) {
  // A pin in a bore of the same radius, both the same 32-sided polygon (one
  // tessellator, one radius): the facets coincide, the depth is 0. Each
  // facet of the pin crosses the block's rims, where no single face bounds
  // it; moving the pieces off the bore (ShiftOffBound) settles them, where
  // before a measurement refined every rim to an eighth of the resolution
  // (about 100,000 sub-triangles).
  const TriangleMesh block = MakeSolidOfRevolution({{4, 0}, {8, 0}, {8, 5}, {4, 5}}, 32);
  const TriangleMesh pin = Post(4, 32);
  const SurfaceDepth depth = Measure(pin, block, 5e-3);
  EXPECT_LE(depth.upper, 5e-3);
  EXPECT_LT(depth.sub_triangles, 10000);
  // Pushed 0.1 sideways the pin is 0.1 deep in the bore's wall, and found so.
  const DepthSurface sa(OneShell(pin)), sb(OneShell(block));
  SurfaceDepthOptions options;
  options.resolution = 5e-3;
  const SurfaceDepth pushed = MeasureSurfaceDepth(sa, Eigen::Isometry3d(Eigen::Translation3d(0.1, 0, 0)), sb, options);
  EXPECT_GE(pushed.upper, 0.09);
}

TEST(MeshDepth, PinInABlockWithAHoleClosedAndWithBoundaryEdges) {
  // Four segments turn the profile into a square block with a square hole,
  // both rotated 45 degrees: the hole's sides lie on |x| + |y| = 2. A square
  // pin of half-width 1.5 reaches |x| + |y| = 3 at its edges: 1 / sqrt(2)
  // into the block's material (the hole's sides' points inside the pin are
  // at most 0.5 from the pin's faces).
  TriangleMesh block = MakeSolidOfRevolution({{2, 0}, {5, 0}, {5, 3}, {2, 3}}, 4);
  const TriangleMesh pin = MakeBox({-1.5, -1.5, -5}, {1.5, 1.5, 10});
  const SurfaceDepth closed = Measure(pin, block);
  EXPECT_NEAR(closed.upper, std::sqrt(0.5), 1e-3 + 1e-12);
  // An export with a gap: one small triangle of the outer wall missing
  // (the block subdivided twice: the gap is 0.3% of its area).
  block = Subdivided(Subdivided(block));
  Shell open = OneShell(block);
  int outer = -1;
  for (int t = 0; t < static_cast<int>(open.triangles.size()) && outer < 0; ++t) {
    const auto& tri = open.triangles[t];
    if (open.vertices[tri[0]].head<2>().lpNorm<1>() > 4.9 && open.vertices[tri[1]].head<2>().lpNorm<1>() > 4.9 &&
        open.vertices[tri[2]].head<2>().lpNorm<1>() > 4.9)
      outer = t;
  }
  ASSERT_GE(outer, 0);
  block.triangles.erase(block.triangles.begin() + open.source_triangles[outer]);
  const Shell gap = OneShell(block);
  EXPECT_FALSE(gap.closed);
  const DepthSurface surface(gap);
  EXPECT_FALSE(surface.oriented());
  EXPECT_TRUE(surface.solid());                       // a gap, not an opening
  EXPECT_GT(surface.SignedDistance({3, 0, 1.5}), 0);  // in the material: the winding number
  EXPECT_LT(surface.SignedDistance({0, 0, 1.5}), 0);  // in the hole
  SurfaceDepthOptions options;
  options.resolution = 1e-3;
  const SurfaceDepth depth =
      MeasureSurfaceDepth(DepthSurface(OneShell(pin)), Eigen::Isometry3d::Identity(), surface, options);
  EXPECT_NEAR(depth.upper, std::sqrt(0.5), 1e-3 + 1e-12);
}

// A sphere (radius 10) cut by a crop just below its top (z < 9.85: the cut
// is 0.7% of its area, so the cut shell is still a solid) answers inside or
// outside as the whole sphere does at every point of the crop's box, by its
// pseudo-normals where its nearest point is nearer than the box's faces.
// With a triangle missing inside the box (a crack the crop did not make)
// the pseudo-normals are not trusted: the winding number answers.
TEST(MeshDepth, AShellTheCropCutAnswersInsideAsTheWholeShellDoes) {
  std::vector<Eigen::Vector2d> profile;
  constexpr int kRings = 48;
  for (int i = 0; i <= kRings; ++i) {
    const double angle = M_PI * i / kRings;
    profile.emplace_back(i == 0 || i == kRings ? 0.0 : 10 * std::sin(angle), -10 * std::cos(angle));
  }
  const TriangleMesh sphere = MakeSolidOfRevolution(profile, 48);
  Aabb box;
  box.min = Eigen::Vector3d(-20, -20, -20);
  box.max = Eigen::Vector3d(20, 20, 9.85);
  const TriangleMesh cut = CropMesh(sphere, box);
  ASSERT_LT(cut.triangles.size(), sphere.triangles.size());
  const DepthSurface whole(OneShell(sphere)), cropped(OneShell(cut));
  ASSERT_TRUE(whole.oriented());
  ASSERT_FALSE(cropped.oriented());
  ASSERT_TRUE(cropped.solid());
  EXPECT_TRUE(cropped.inside_by_normal_within_crop());
  std::mt19937 random(7);
  std::uniform_real_distribution<double> xy(-12, 12), z(-12, 9.85);
  int checked = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::Vector3d p(xy(random), xy(random), z(random));
    const double expected = whole.SignedDistance(p);
    if (std::abs(expected) < 1e-6) continue;
    ++checked;
    EXPECT_EQ(cropped.SignedDistance(p) > 0, expected > 0) << p.transpose();
  }
  EXPECT_GT(checked, 3900);
  // The same cut with one more triangle missing, at the equator.
  TriangleMesh cracked = cut;
  for (std::size_t t = 0; t < cracked.triangles.size(); ++t) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int v : cracked.triangles[t]) centre += cracked.vertices[v] / 3;
    if (std::abs(centre.z()) < 0.5) {
      cracked.triangles.erase(cracked.triangles.begin() + static_cast<std::ptrdiff_t>(t));
      break;
    }
  }
  ASSERT_EQ(cracked.triangles.size() + 1, cut.triangles.size());
  const DepthSurface with_crack(OneShell(cracked));
  ASSERT_TRUE(with_crack.solid());
  EXPECT_FALSE(with_crack.inside_by_normal_within_crop());
}

TEST(MeshDepth, ABowlIsASheetNotASolid) {
  // A sphere of radius 10 open above 35 degrees from the pole (9% of it
  // missing: more than a gap): the air it holds is not material, a rod in
  // it is not inside it, a box through its wall is as deep as the wall's
  // points inside the box.
  TriangleMesh bowl;
  const int rings = 24, segments = 48;
  for (int i = 0; i < rings; ++i) {
    const double theta = (35.0 + 145.0 * i / rings) * M_PI / 180;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * M_PI * j / segments;
      bowl.vertices.emplace_back(10 * std::sin(theta) * std::cos(phi), 10 * std::sin(theta) * std::sin(phi),
                                 10 * std::cos(theta));
    }
  }
  bowl.vertices.emplace_back(0, 0, -10);  // the pole
  const int pole = rings * segments;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      if (i + 1 == rings) {
        bowl.triangles.push_back({a, pole, b});
        continue;
      }
      bowl.triangles.push_back({a, a + segments, b + segments});
      bowl.triangles.push_back({a, b + segments, b});
    }
  const DepthSurface sheet(OneShell(bowl));
  EXPECT_FALSE(sheet.solid());
  EXPECT_LT(sheet.SignedDistance({0, 0, 0}), 0);
  EXPECT_EQ(Measure(MakeBox({-2, -0.5, -0.5}, {2, 0.5, 0.5}), bowl).upper, 0);
  // A box across the bottom of the wall, 1 below and 1 above it: the wall's
  // points inside it are at most 1 from its faces (its half-height).
  const SurfaceDepth through = Measure(MakeBox({-1, -1, -11}, {1, 1, -9}), bowl);
  EXPECT_GT(through.upper, 0.9);
  EXPECT_LE(through.upper, 1 + 1e-3 + 1e-12);
  // The same sphere closed: a solid ball, the rod deep inside.
  EXPECT_TRUE(DepthSurface(OneShell(MakeSolidOfRevolution({{0, -10}, {10, 0}, {0, 10}}, 16))).solid());
}

TEST(MeshDepth, ThickFeaturesCannotPassThroughEachOther) {
  // A pin of radius 1 halfway through a wall 2 thick (no hole): deep, though
  // no vertex of either is inside the other.
  const TriangleMesh wall = MakeBox({-20, -20, -1}, {20, 20, 1});
  const TriangleMesh pin = MakeSolidOfRevolution({{0, -30}, {1, -30}, {1, 30}, {0, 30}}, 32);
  const SurfaceDepth depth = Measure(pin, wall, 1e-3);
  EXPECT_GT(depth.lower, 0.9);  // the wall's faces inside the pin: up to its radius deep
}

}  // namespace
}  // namespace ausbau
