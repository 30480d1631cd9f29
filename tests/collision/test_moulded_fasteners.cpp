// Fasteners moulded into one welded solid (geometry/protrusions.h,
// collision/rigid_depth.h MouldedFastener): a plate with a block standing
// out of it, welded into one closed shell, against boxes of S, with depths
// that can be checked by hand.
#include <gtest/gtest.h>

#include <array>

#include "collision/mesh_depth.h"
#include "collision/rigid_depth.h"
#include "fixtures/welded_union.h"
#include "geometry/primitives.h"
#include "geometry/protrusions.h"
#include "geometry/shells.h"

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

// Appends the quad a b c d (a loop) as two triangles facing `outward`.
void Quad(TriangleMesh& mesh, std::array<int, 4> q, const Vec3& outward) {
  const Vec3 normal = (mesh.vertices[q[1]] - mesh.vertices[q[0]]).cross(mesh.vertices[q[2]] - mesh.vertices[q[0]]);
  if (normal.dot(outward) < 0) std::swap(q[1], q[3]);
  mesh.triangles.push_back({q[0], q[1], q[2]});
  mesh.triangles.push_back({q[0], q[2], q[3]});
}

// The plate [0, 100] x [0, 60] x [0, 3] with the block [bx0, bx1] x [by0,
// by1] x [-h, 0] under it, welded into one closed shell: the plate's bottom
// face is the ring around the block's footprint.
TriangleMesh PlateWithBlock(double bx0, double bx1, double by0, double by1, double h) {
  TriangleMesh mesh;
  const auto add = [&](double x, double y, double z) {
    mesh.vertices.emplace_back(x, y, z);
    return static_cast<int>(mesh.vertices.size()) - 1;
  };
  const double xs[2] = {0, 100}, ys[2] = {0, 60};
  int bottom[4], top[4], foot[4], tip[4];  // corners in the order (x0,y0) (x1,y0) (x1,y1) (x0,y1)
  const double bxs[2] = {bx0, bx1}, bys[2] = {by0, by1};
  const int order[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) {
    bottom[k] = add(xs[order[k][0]], ys[order[k][1]], 0);
    top[k] = add(xs[order[k][0]], ys[order[k][1]], 3);
    foot[k] = add(bxs[order[k][0]], bys[order[k][1]], 0);
    tip[k] = add(bxs[order[k][0]], bys[order[k][1]], -h);
  }
  Quad(mesh, {top[0], top[1], top[2], top[3]}, Vec3::UnitZ());
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    const Vec3 side = (mesh.vertices[bottom[k]] + mesh.vertices[bottom[n]] - Vec3(100, 60, 0)).normalized();
    Quad(mesh, {bottom[k], bottom[n], top[n], top[k]}, side);              // the plate's rim
    Quad(mesh, {bottom[k], bottom[n], foot[n], foot[k]}, -Vec3::UnitZ());  // the ring around the footprint
    const Vec3 wall =
        (mesh.vertices[foot[k]] + mesh.vertices[foot[n]] - 2 * Vec3(0.5 * (bx0 + bx1), 0.5 * (by0 + by1), 0))
            .cwiseProduct(Vec3(1, 1, 0))
            .normalized();
    Quad(mesh, {foot[k], foot[n], tip[n], tip[k]}, wall);  // the block's walls
  }
  Quad(mesh, {tip[0], tip[1], tip[2], tip[3]}, -Vec3::UnitZ());
  return mesh;
}

Shell OneShell(const TriangleMesh& mesh) {
  auto shells = SplitIntoShells(mesh);
  EXPECT_EQ(shells.size(), 1u);
  return shells.front();
}

TEST(MouldedFasteners, TheTestPlateIsOneClosedNonConvexSolid) {
  const Shell shell = OneShell(PlateWithBlock(70, 73, 20, 32, 7));
  EXPECT_TRUE(shell.closed);
  EXPECT_FALSE(shell.convex);
  EXPECT_NEAR(shell.volume, 100 * 60 * 3 + 3 * 12 * 7, 1e-6);
}

TEST(MouldedFasteners, FindsThePlateAndTheBlockStandingOutOfIt) {
  const Shell shell = OneShell(PlateWithBlock(70, 73, 20, 32, 7));
  const PlateFeatures plate = FindPlateFeatures(shell);
  ASSERT_TRUE(plate.found) << plate.reason;
  EXPECT_NEAR(std::abs(plate.normal.z()), 1.0, 1e-12);
  const double sign = plate.normal.z();  // the offsets follow the normal's sign
  EXPECT_NEAR(std::min(plate.low, plate.high), sign > 0 ? 0.0 : -3.0, 1e-9);
  EXPECT_NEAR(std::max(plate.low, plate.high), sign > 0 ? 3.0 : 0.0, 1e-9);
  ASSERT_EQ(plate.features.size(), 1u);
  const Protrusion& block = plate.features.front();
  EXPECT_EQ(block.triangles.size(), 10u);  // four walls and the tip
  EXPECT_NEAR(block.volume, 3 * 12 * 7, 1e-6);
  // The box holds the block (every corner of it), grown by a quarter of the
  // plate's thickness, and nothing of the plate but its face.
  EXPECT_TRUE(block.box.Contains({70, 20, -7}));
  EXPECT_TRUE(block.box.Contains({73, 32, 0}));
  EXPECT_TRUE(block.box.Contains({73.7, 32.7, -7.7}));
  EXPECT_FALSE(block.box.Contains({73.8, 26, -3}));
  EXPECT_FALSE(block.box.Contains({71, 26, 0.01}));  // inside the plate
  EXPECT_FALSE(block.box.Contains({71, 26, -7.8}));
}

TEST(MouldedFasteners, ABlockOrABracketIsNoPlate) {
  EXPECT_FALSE(FindPlateFeatures(OneShell(MakeBox({0, 0, 0}, {10, 10, 10}))).found);  // convex
  // An L-bracket of two equal legs: its largest opposite faces hold less
  // than a fifth of its area each... or it is a plate whose other leg is a
  // feature: either way the split must not make a leg a fastener (the
  // size rule, below).
  const PlateFeatures l =
      FindPlateFeatures(OneShell(MakePrism({{0, 0}, {40, 0}, {40, 3}, {3, 3}, {3, 40}, {0, 40}}, 0, 30)));
  if (l.found) {
    for (const auto& f : l.features) EXPECT_GT(f.volume, 0.05 * (40 * 3 + 37 * 3) * 30);
  }
}

TEST(MouldedFasteners, MaskedDepthLeavesTheFastenerOut) {
  const Shell shell = OneShell(PlateWithBlock(70, 73, 20, 32, 7));
  const PlateFeatures plate = FindPlateFeatures(shell);
  ASSERT_TRUE(plate.found);
  DepthMask mask;
  mask.boxes.push_back(plate.features.front().box);
  mask.skip_triangle.assign(shell.triangles.size(), 0);
  for (int t : plate.features.front().triangles) mask.skip_triangle[t] = 1;
  // S: a box the block reaches 1 mm into (x from 72), below the plate.
  const DepthSurface d(shell), s(OneShell(MakeBox({72, 15, -6}, {80, 40, -4})));
  SurfaceDepthOptions options;
  options.resolution = 1e-3;
  const SurfaceDepth whole = MeasureSurfaceDepth(d, Eigen::Isometry3d::Identity(), s, options);
  EXPECT_NEAR(whole.upper, 1.0, 2e-3);
  const SurfaceDepth rest = MeasureSurfaceDepth(d, Eigen::Isometry3d::Identity(), s, options, &mask);
  EXPECT_LE(rest.upper, 1e-3);
  // D moved 1 mm down: the block now also sits 1 mm deeper, left out, but a
  // box of S under the plate's face is 0.5 mm inside the plate.
  const DepthSurface under(OneShell(MakeBox({10, 10, -2}, {20, 20, -0.5})));
  const Eigen::Isometry3d down(Eigen::Translation3d(0, 0, -1));
  EXPECT_NEAR(MeasureSurfaceDepth(d, down, under, options, &mask).upper, 0.5, 2e-3);
  // A box of S that passes through the block into the plate above it is
  // inside the plate's rest, whatever the mask says about the block.
  const DepthSurface through(OneShell(MakeBox({71, 25, -3}, {72, 27, 1})));
  EXPECT_GE(MeasureSurfaceDepth(d, Eigen::Isometry3d::Identity(), through, options, &mask).upper, 0.5 - 2e-3);
}

TEST(MouldedFasteners, ABoxPressedIntoTheFaceBesideTheBlock) {
  // A box of S pressed 0.01 into the plate's bottom face (the ring around
  // the block's footprint), 1 mm beside the block: 0.01 deep, both ways.
  const DepthSurface d(OneShell(PlateWithBlock(70, 73, 20, 32, 7)));
  const DepthSurface s(OneShell(MakeBox({40, 10, -5}, {69, 50, 0.01})));
  SurfaceDepthOptions options;
  options.resolution = 1e-3;
  const SurfaceDepth depth = MeasureSurfaceDepth(s, Eigen::Isometry3d::Identity(), d, options);
  EXPECT_NEAR(depth.upper, 0.01, 1e-3 + 1e-12);
  EXPECT_GE(depth.lower, 0.01 - 1e-9);
  const SurfaceDepth other = MeasureSurfaceDepth(d, Eigen::Isometry3d::Identity(), s, options);
  EXPECT_NEAR(other.upper, 0.01, 1e-3 + 1e-12);
}

TEST(MouldedFasteners, ClassifyPartsSplitsTheClashIntoARigidPlateAndAFastener) {
  const TriangleMesh d = PlateWithBlock(70, 73, 20, 32, 7);
  TriangleMesh s = MakeBox({72, 15, -6}, {80, 40, -4});  // the block's hook reach: 1 mm
  s.Append(MakeBox({10, 10, -2}, {20, 20, -0.2}));       // 0.2 mm under the plate
  const double tolerance = 0.05;
  const auto parts = ClassifyParts(d, s, Pose(), tolerance);
  EXPECT_TRUE(parts->rigid_interference.empty()) << parts->moulded_note;
  ASSERT_EQ(parts->moulded.size(), 1u);
  EXPECT_EQ(parts->FastenerCount(), 1);
  EXPECT_EQ(parts->moulded.front().triangles, 10);
  EXPECT_NEAR(parts->moulded.front().installed_depth, 1.0, 0.1);
  const RigidDepthChecker checker(parts, tolerance / 2, tolerance / 4);
  const DepthReport installed = checker.Measure(Pose());
  EXPECT_LE(installed.rigid_depth, 0.0);            // the plate is 0.2 above S
  EXPECT_NEAR(installed.fastener_depth, 1.0, 0.1);  // reported
  // Down 0.5 mm: the plate is 0.3 mm inside the box under it.
  Pose down = Pose();
  down.t = Vec3(0, 0, -0.5);
  EXPECT_NEAR(checker.Measure(down).rigid_depth, 0.3, 0.03);
  // Pulled out along +x... the block's hook side: the fastener bends, the
  // plate is free: valid.
  Pose pulled = Pose();
  pulled.t = Vec3(2, 0, 0);
  EXPECT_LE(checker.Measure(pulled).rigid_depth, tolerance / 2);
}

TEST(MouldedFasteners, AMouldedFastenerBendsOnlyIntoTheSolidItEngages) {
  // The block hooks 1 mm into a box of S; a second box, 0.5 mm from that
  // one and 0.7 mm under the block's tip, is a solid of S it does not
  // engage at the installed pose.
  const TriangleMesh d = PlateWithBlock(70, 73, 20, 32, 7);
  TriangleMesh s = MakeBox({72, 15, -6}, {80, 40, -4});
  s.Append(MakeBox({66, 20, -12}, {71.5, 32, -7.7}));
  const double tolerance = 0.05;
  const auto parts = ClassifyParts(d, s, Pose(), tolerance);
  ASSERT_EQ(parts->moulded.size(), 1u) << parts->moulded_note;
  EXPECT_EQ(parts->static_solid, (std::vector<int>{0, 1}));
  EXPECT_TRUE(parts->Engages(0, 0));
  EXPECT_FALSE(parts->Engages(0, 1));
  const RigidDepthChecker checker(parts, tolerance / 2, tolerance / 4);
  EXPECT_TRUE(checker.IsValid(Pose()));
  Pose pulled = Pose();
  pulled.t = Vec3(2, 0, 0);
  EXPECT_TRUE(checker.IsValid(pulled));  // the block bends in the box it hooks
  Pose down = Pose();
  down.t = Vec3(0, 0, -1);
  EXPECT_FALSE(checker.IsValid(down));  // its tip 0.3 mm into the other box
  const DepthReport report = checker.Measure(down);
  EXPECT_EQ(report.rigid_static_shell, 1);
  EXPECT_NEAR(report.rigid_depth, 0.3, 0.03);
}

TEST(MouldedFasteners, AFeatureTooLargeToBeAFastenerStaysAClash) {
  // The same plate, its block 40 x 40 x 7: 11.2 kmm^3 against 18 kmm^3 of
  // plate, far over a fastener's 5%: a clash, with the reason (2 mm deep:
  // no press fit either).
  const TriangleMesh d = PlateWithBlock(30, 70, 10, 50, 7);
  const TriangleMesh s = MakeBox({68, 0, -6}, {80, 60, -4});
  const auto parts = ClassifyParts(d, s, Pose(), 0.05);
  EXPECT_EQ(parts->rigid_interference.size(), 1u);
  EXPECT_TRUE(parts->moulded.empty());
  EXPECT_NE(parts->moulded_note.find("more than a fastener"), std::string::npos) << parts->moulded_note;
}

TEST(MouldedFasteners, ThePlateItselfInSIsAClash) {
  const TriangleMesh d = PlateWithBlock(70, 73, 20, 32, 7);
  TriangleMesh s = MakeBox({72, 15, -6}, {80, 40, -4});
  s.Append(MakeBox({10, 10, -2}, {20, 20, 1.0}));  // 1 mm into the plate's face: no press fit
  const auto parts = ClassifyParts(d, s, Pose(), 0.05);
  EXPECT_EQ(parts->rigid_interference.size(), 1u);
  EXPECT_TRUE(parts->moulded.empty());
  EXPECT_NE(parts->moulded_note.find("the plate itself"), std::string::npos) << parts->moulded_note;
}

TEST(MouldedFasteners, AFitThatAFeatureHoldsIsAClipOnceTheShellHasMouldedFasteners) {
  // The plate with two blocks under it, welded: block A hooks 1 mm into a
  // box of S (a clash), block B only 0.3 mm into another, a thin layer
  // along B's +x face that slides out along y or z: alone, a press fit. On
  // a plate whose features hold clips, B is a clip too (its box-soup twin,
  // a solid of its own, is a fastener): two moulded fasteners, no fit.
  const TriangleMesh plate_and_blocks = WeldedUnion(
      {MakeBox({0, 0, 0}, {100, 60, 3}), MakeBox({70, 20, -7}, {73, 32, 1}), MakeBox({20, 20, -7}, {23, 32, 1})});
  const TriangleMesh hook_a = MakeBox({72, 15, -6}, {80, 40, -4});
  TriangleMesh both = hook_a;
  both.Append(MakeBox({22.7, 15, -6}, {30, 40, -4}));
  const double tolerance = 0.05;
  // B alone: all the shell's interference is that layer, a fit.
  const auto only_b = ClassifyParts(plate_and_blocks, MakeBox({22.7, 15, -6}, {30, 40, -4}), Pose(), tolerance);
  EXPECT_EQ(only_b->fits.size(), 1u);
  EXPECT_TRUE(only_b->moulded.empty());
  EXPECT_TRUE(only_b->rigid_interference.empty());

  const auto parts = ClassifyParts(plate_and_blocks, both, Pose(), tolerance);
  EXPECT_TRUE(parts->rigid_interference.empty()) << parts->moulded_note;
  EXPECT_TRUE(parts->fits.empty());
  ASSERT_EQ(parts->moulded.size(), 2u);
  // Pulled 2 mm along +x: B's layer deepens to 2.3 mm, A's hook bends
  // (their surfaces reach 1.5 mm into S, reported); the plate is free. With
  // B a fit, that pose was invalid.
  const RigidDepthChecker checker(parts, tolerance / 2, tolerance / 4);
  Pose pulled = Pose();
  pulled.t = Vec3(2, 0, 0);
  const DepthReport report = checker.Measure(pulled);
  EXPECT_LE(report.rigid_depth, tolerance / 2);
  EXPECT_GT(report.fastener_depth, 1.0);
}

}  // namespace
}  // namespace ausbau
