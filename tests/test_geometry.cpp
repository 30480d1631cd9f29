// Poses, the thesis metric (eq. 2) and range (eq. 3), interpolation, bounds
// and the disassembly goal region, on hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/random.h"
#include "geometry/closest_point.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "geometry/triangle_box.h"
#include "geometry/triangle_bvh.h"
#include "geometry/weld.h"
#include "planning/state_space.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using testing::PoseAt;

TEST(Metric, TranslationIsScaledByTheBoundsExtent) {
  Metric metric{10.0};
  EXPECT_DOUBLE_EQ(metric.Translation({0, 0, 0}, {3, 4, 0}), 0.5);
  EXPECT_DOUBLE_EQ(metric.Translation({1, 1, 1}, {1, 1, 1}), 0.0);
}

TEST(Metric, RotationIsHalfAngleOverPi) {
  // A rotation by angle a about any axis: q1.q2 = cos(a/2), d'_q = (a/2)/pi.
  EXPECT_NEAR(Metric::Rotation(PoseAt(0, 0, 0).q, PoseAt(0, 0, 0, M_PI / 2).q), 0.25, 1e-12);
  EXPECT_NEAR(Metric::Rotation(PoseAt(0, 0, 0).q, PoseAt(0, 0, 0, M_PI).q), 0.5, 1e-12);
  // q and -q are the same rotation: distance 0.
  Eigen::Quaterniond q = PoseAt(0, 0, 0, 1.0, {1, 2, 3}).q;
  Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
  EXPECT_NEAR(Metric::Rotation(q, minus_q), 0.0, 1e-7);
}

TEST(Metric, ConvexCombinationOfTranslationAndRotation) {
  Metric metric{10.0};
  const Pose a = PoseAt(0, 0, 0), b = PoseAt(3, 4, 0, M_PI / 2);
  // d'_t = 0.5, d'_q = 0.25
  EXPECT_NEAR(metric.Distance(a, b, 0.5), 0.375, 1e-12);
  EXPECT_NEAR(metric.Distance(a, b, 0.2), 0.2 * 0.5 + 0.8 * 0.25, 1e-12);
  EXPECT_NEAR(metric.Distance(a, b, 0.583), 0.583 * 0.5 + 0.417 * 0.25, 1e-12);
  EXPECT_NEAR(metric.Distance(b, a, 0.3), metric.Distance(a, b, 0.3), 1e-15);
}

TEST(Metric, RangeIsTheLargerOfTranslationAndRotation) {
  Metric metric{10.0};
  EXPECT_NEAR(metric.Range(PoseAt(0, 0, 0), PoseAt(3, 4, 0, M_PI / 2)), 0.5, 1e-12);
  EXPECT_NEAR(metric.Range(PoseAt(0, 0, 0), PoseAt(1, 0, 0, M_PI)), 0.5, 1e-12);
  EXPECT_NEAR(metric.Range(PoseAt(0, 0, 0), PoseAt(1, 0, 0, M_PI / 2)), 0.25, 1e-12);
}

TEST(Interpolation, LinearInTranslationAndSlerpInRotation) {
  const Pose a = PoseAt(0, 0, 0), b = PoseAt(2, 4, 6, M_PI / 2, {1, 0, 0});
  const Pose mid = Interpolate(a, b, 0.5);
  EXPECT_TRUE(mid.t.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_NEAR(RotationAngle(a.q, mid.q), M_PI / 4, 1e-12);
  EXPECT_NEAR(RotationAngle(mid.q, b.q), M_PI / 4, 1e-12);
  EXPECT_TRUE(Interpolate(a, b, 0.0).q.isApprox(a.q));
  EXPECT_TRUE(Interpolate(a, b, 1.0).q.isApprox(b.q));
}

TEST(Interpolation, TakesTheShorterArcWhateverTheSign) {
  const Pose a = PoseAt(0, 0, 0, 0.2);
  Pose b = PoseAt(0, 0, 0, 0.6);
  b.q.coeffs() = -b.q.coeffs();  // same rotation, other hemisphere
  EXPECT_NEAR(RotationAngle(a.q, Interpolate(a, b, 0.5).q), 0.2, 1e-12);
}

TEST(Interpolation, MaxDisplacementBoundsEveryVertexMotion) {
  // A unit-radius point turned by 90 degrees moves sqrt(2) (chord) <= pi/2 (arc).
  const Pose a = PoseAt(0, 0, 0), b = PoseAt(1, 0, 0, M_PI / 2);
  EXPECT_NEAR(MaxDisplacement(a, b, 1.0), 1.0 + M_PI / 2, 1e-12);
  Random random(3);
  for (int i = 0; i < 100; ++i) {
    Eigen::Vector3d p(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1));
    p = p.normalized() * random.Uniform01();
    const double s0 = random.Uniform01(), s1 = random.Uniform01();
    const double moved = (Interpolate(a, b, s1).Apply(p) - Interpolate(a, b, s0).Apply(p)).norm();
    EXPECT_LE(moved, std::abs(s1 - s0) * MaxDisplacement(a, b, 1.0) + 1e-12);
  }
}

TEST(Aabb, SeparationIsStrict) {
  Aabb a, b;
  a.Extend(Eigen::Vector3d(0, 0, 0));
  a.Extend(Eigen::Vector3d(1, 1, 1));
  b.Extend(Eigen::Vector3d(1, 0, 0));
  b.Extend(Eigen::Vector3d(2, 1, 1));
  EXPECT_FALSE(a.SeparatedFrom(b));  // touching faces
  b.min.x() = 1.001;
  EXPECT_TRUE(a.SeparatedFrom(b));
  EXPECT_TRUE(b.SeparatedFrom(a));
}

PlanningProblem BoxProblem() {
  PlanningProblem problem;
  problem.robot = MakeBox({-1, -0.5, -0.5}, {1, 0.5, 0.5});
  problem.environment = MakeBox({-2, -2, -2}, {2, 2, 2});
  problem.robot_local_box = problem.robot.Bounds();
  problem.environment_box = problem.environment.Bounds();
  problem.bounds.min = {-10, -10, -10};
  problem.bounds.max = {10, 10, 10};
  problem.metric.nu = problem.bounds.Diagonal();
  return problem;
}

TEST(GoalRegion, SeparatedBoundingBoxes) {
  const PlanningProblem problem = BoxProblem();
  EXPECT_FALSE(problem.InGoalRegion(PoseAt(0, 0, 0)));
  EXPECT_FALSE(problem.InGoalRegion(PoseAt(3.0, 0, 0)));  // robot spans x in [2, 4]: touches
  EXPECT_TRUE(problem.InGoalRegion(PoseAt(3.01, 0, 0)));
  // Turned by 90 degrees about z the robot is 1 wide in x: x in [2.01, 3.01].
  EXPECT_TRUE(problem.InGoalRegion(PoseAt(2.51, 0, 0, M_PI / 2)));
  EXPECT_FALSE(problem.InGoalRegion(PoseAt(2.49, 0, 0, M_PI / 2)));
}

TEST(GoalRegion, RobotBoxIsConservative) {
  const PlanningProblem problem = BoxProblem();
  Random random(7);
  for (int i = 0; i < 200; ++i) {
    const Pose pose = problem.SampleUniform(random);
    const Aabb box = problem.RobotBoxAt(pose);
    for (const auto& v : problem.robot.vertices) {
      EXPECT_TRUE((pose.Apply(v).array() >= box.min.array() - 1e-9).all());
      EXPECT_TRUE((pose.Apply(v).array() <= box.max.array() + 1e-9).all());
    }
  }
}

TEST(StateSpace, SceneAndPlanningConventionsRoundTrip) {
  PlanningProblem problem = BoxProblem();
  problem.reference_point = {5, 6, 7};
  problem.dynamic_origin = {0, 0, 0};
  const Pose scene_pose = PoseAt(1, 2, 3, 0.7, {1, 1, 0});
  const Pose planning = problem.SceneToPlanning(scene_pose);
  // The same mesh point lands in the same place in both conventions.
  const Eigen::Vector3d x(1.5, -2, 0.25);
  EXPECT_TRUE((scene_pose.q * (x - problem.dynamic_origin) + scene_pose.t)
                  .isApprox(planning.q * (x - problem.reference_point) + planning.t));
  const Pose back = problem.PlanningToScene(planning);
  EXPECT_TRUE(back.t.isApprox(scene_pose.t));
}

TEST(StateSpace, UniformSamplesStayInBounds) {
  PlanningProblem problem = BoxProblem();
  problem.bounded_point = {1, 0, 0};
  Random random(11);
  for (int i = 0; i < 1000; ++i) EXPECT_TRUE(problem.InBounds(problem.SampleUniform(random)));
}

TEST(Random, SameSeedSameStream) {
  Random a(42), b(42), c(43);
  for (int i = 0; i < 10; ++i) {
    const double x = a.Uniform01();
    EXPECT_EQ(x, b.Uniform01());
    EXPECT_GE(x, 0.0);
    EXPECT_LT(x, 1.0);
  }
  EXPECT_NE(Random(42).Uniform01(), c.Uniform01());
  EXPECT_NEAR(a.UniformQuaternion().norm(), 1.0, 1e-12);
}

// ---------------------------------------------------------------- closest point on a triangle

// The triangle (0,0,0), (1,0,0), (0,1,0): each Voronoi region has a point
// whose answer can be read off. Every variant of the kernel agrees on a
// proper triangle (and here exactly: the numbers are dyadic).
struct ClosestPointCase {
  const char* region;
  Eigen::Vector3d p, expected_point, expected_weights;
};

TEST(ClosestPointOnTriangle, EachVoronoiRegion) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const ClosestPointCase cases[] = {
      {"vertex a", {-1, -1, 0.5}, {0, 0, 0}, {1, 0, 0}},
      {"vertex b", {2, -0.5, -1}, {1, 0, 0}, {0, 1, 0}},
      {"vertex c", {-0.5, 2, 1}, {0, 1, 0}, {0, 0, 1}},
      {"edge ab", {0.5, -1, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}},
      {"edge ac", {-1, 0.25, 3}, {0, 0.25, 0}, {0.75, 0, 0.25}},
      {"edge bc", {1, 1, -2}, {0.5, 0.5, 0}, {0, 0.5, 0.5}},
      {"face", {0.25, 0.25, 2}, {0.25, 0.25, 0}, {0.5, 0.25, 0.25}},
  };
  const DegenerateTriangles policies[] = {DegenerateTriangles::kUnguarded, DegenerateTriangles::kNearestEdgePoint,
                                          DegenerateTriangles::kNearestCorner};
  const FaceWeights roundings[] = {FaceWeights::kTimesReciprocalOfSum, FaceWeights::kDividedBySum};
  for (const ClosestPointCase& test : cases) {
    for (DegenerateTriangles policy : policies) {
      for (FaceWeights rounding : roundings) {
        Eigen::Vector3d weights;
        const Eigen::Vector3d q = ClosestPointOnTriangle(test.p, a, b, c, policy, rounding, &weights);
        EXPECT_EQ(q, test.expected_point) << test.region;
        EXPECT_EQ(weights, test.expected_weights) << test.region;
        EXPECT_EQ(ClosestPointOnTriangle(test.p, a, b, c, policy, rounding), q) << test.region;
      }
    }
  }
}

TEST(ClosestPointOnTriangle, OnTheBoundaryBetweenRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  // On the line that bounds vertex a's region and edge ab's: the vertex.
  EXPECT_EQ(
      ClosestPointOnTriangle({0, -1, 0}, a, b, c, DegenerateTriangles::kUnguarded, FaceWeights::kTimesReciprocalOfSum),
      a);
  // A point of the triangle is its own closest point.
  EXPECT_EQ(ClosestPointOnTriangle({0.5, 0.5, 0}, a, b, c, DegenerateTriangles::kUnguarded,
                                   FaceWeights::kTimesReciprocalOfSum),
            Eigen::Vector3d(0.5, 0.5, 0));
}

TEST(ClosestPointOnTriangle, CoincidentCornersAreGuardedOnlyWhereAsked) {
  // a == b: the closest point falls in edge ab's region, whose division is
  // 0 / 0. Guarded, the edge answers its first corner; unguarded, NaN (a
  // BVH search then never takes the triangle as nearest).
  const Eigen::Vector3d a(0, 0, 0), b(0, 0, 0), c(1, 0, 0), p(0.5, 1, 0);
  EXPECT_EQ(
      ClosestPointOnTriangle(p, a, b, c, DegenerateTriangles::kNearestEdgePoint, FaceWeights::kTimesReciprocalOfSum),
      a);
  EXPECT_TRUE(std::isnan(
      ClosestPointOnTriangle(p, a, b, c, DegenerateTriangles::kUnguarded, FaceWeights::kTimesReciprocalOfSum).x()));
  EXPECT_TRUE(std::isnan(
      ClosestPointOnTriangle(p, a, b, c, DegenerateTriangles::kNearestCorner, FaceWeights::kDividedBySum).x()));
}

// ---------------------------------------------------------------- triangle against box

// The box [-1, 1]^3 with each rounding (a cube, so both apply).
bool OverlapsUnitBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                     SatRounding rounding) {
  return TriangleOverlapsBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), a, b, c, rounding);
}

TEST(TriangleOverlapsBox, EachSeparatingAxisType) {
  for (SatRounding rounding : {SatRounding::kPerAxisHalfExtent, SatRounding::kCubeHalfSize}) {
    // Inside, and crossing the box.
    EXPECT_TRUE(OverlapsUnitBox({-0.5, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0.2}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({-5, -5, 0}, {5, -5, 0}, {0, 5, 0}, rounding));
    // A box face normal: all of the triangle beyond x = 1; touching it counts.
    EXPECT_FALSE(OverlapsUnitBox({1.5, 0, 0}, {2, 1, 0}, {2, 0, 1}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({1, 0, 0}, {2, 1, 0}, {2, 0, 1}, rounding));
    // The triangle's normal: the plane x + y + z = 3.5 passes the corner
    // (1, 1, 1) (sum 3) while the triangle's box holds the whole cube's
    // extent on every axis and no edge axis separates.
    EXPECT_FALSE(OverlapsUnitBox({3.5, 0, 0}, {0, 3.5, 0}, {0, 0, 3.5}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({2.9, 0, 0}, {0, 2.9, 0}, {0, 0, 2.9}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({3, 0, 0}, {0, 3, 0}, {0, 0, 3}, rounding));  // touches the corner
    // An edge cross product: edge (2.2, 0, 0) -> (0, 2.2, 0) passes the box's
    // z edge at x = y = 1 outside; on axis e_z x edge = (-2.2, -2.2, 0) the
    // triangle projects to [-13.2, -4.84] and the box to [-4.4, 4.4]. The
    // face normals and the triangle's normal do not separate them.
    EXPECT_FALSE(OverlapsUnitBox({2.2, 0, 0}, {0, 2.2, 0}, {3, 3, 5}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({1.8, 0, 0}, {0, 1.8, 0}, {3, 3, 5}, rounding));
  }
}

TEST(TriangleOverlapsBox, BoxAwayFromTheOriginWithUnequalHalfExtents) {
  const Eigen::Vector3d center(10, 20, 30), half(1, 2, 3);
  const auto at = [&](double x, double y, double z) { return Eigen::Vector3d(center + Eigen::Vector3d(x, y, z)); };
  const SatRounding rounding = SatRounding::kPerAxisHalfExtent;
  EXPECT_TRUE(TriangleOverlapsBox(center, half, at(0, 1.9, 0), at(0.5, 1.9, 0), at(0, 1.9, 0.5), rounding));
  EXPECT_FALSE(TriangleOverlapsBox(center, half, at(0, 2.1, 0), at(0.5, 2.1, 0), at(0, 2.1, 0.5), rounding));
  EXPECT_TRUE(TriangleOverlapsBox(center, half, at(0, 0, 2.9), at(0.5, 0, 2.9), at(0, 0.5, 2.9), rounding));
  EXPECT_FALSE(TriangleOverlapsBox(center, half, at(0, 0, 3.1), at(0.5, 0, 3.1), at(0, 0.5, 3.1), rounding));
}

// ---------------------------------------------------------------- vertex welding

TEST(WeldExactPositions, EqualPositionsShareAnIndexInOrderOfFirstAppearance) {
  const std::vector<Eigen::Vector3d> vertices = {{1, 2, 3},       {0, 0, 0},      {1, 2, 3},
                                                 {-0.0, 0, -0.0}, {0, 0, 1e-300}, {0, 0, 0}};
  EXPECT_EQ(WeldExactPositions(vertices), (std::vector<int>{0, 1, 0, 1, 2, 1}));
  EXPECT_TRUE(WeldExactPositions({}).empty());
}

TEST(WeldWithinTolerance, JustInsideAndJustOutside) {
  const double tolerance = 1.0;
  const std::vector<Eigen::Vector3d> vertices = {
      {0, 0, 0}, {1, 0, 0}, {0, std::nextafter(1.0, 2.0), 0}, {0, 0, -1}, {0.75, -0.75, 0}};
  std::vector<Eigen::Vector3d> welded;
  const std::vector<int> euclidean =
      WeldWithinTolerance(vertices, tolerance, WeldDistance::kEuclidean, Eigen::Vector3d::Zero(), tolerance, &welded);
  // At the tolerance: welded; one step beyond: not; (0.75, -0.75) is 1.06 away.
  EXPECT_EQ(euclidean, (std::vector<int>{0, 0, 1, 0, 2}));
  ASSERT_EQ(welded.size(), 3u);
  EXPECT_EQ(welded[0], vertices[0]);  // the first of a group keeps its position
  EXPECT_EQ(welded[1], vertices[2]);
  EXPECT_EQ(welded[2], vertices[4]);
  // Measured by the largest coordinate difference, (0.75, -0.75) is 0.75 away.
  welded.clear();
  const std::vector<int> largest = WeldWithinTolerance(vertices, tolerance, WeldDistance::kLargestCoordinate,
                                                       Eigen::Vector3d::Zero(), tolerance, &welded);
  EXPECT_EQ(largest, (std::vector<int>{0, 0, 1, 0, 0}));
}

TEST(WeldWithinTolerance, ChainsDoNotPropagate) {
  // Vertices 0.75 apart with a tolerance of 1: each is compared with the
  // groups' first vertices only, so a chain breaks into groups of two.
  std::vector<Eigen::Vector3d> vertices;
  for (int i = 0; i < 5; ++i) vertices.emplace_back(0.75 * i, 0, 0);
  std::vector<Eigen::Vector3d> welded;
  const std::vector<int> map =
      WeldWithinTolerance(vertices, 1.0, WeldDistance::kEuclidean, Eigen::Vector3d(-0.3, 0, 0), 1.0, &welded);
  EXPECT_EQ(map, (std::vector<int>{0, 0, 1, 1, 2}));
  ASSERT_EQ(welded.size(), 3u);
  EXPECT_EQ(welded[1].x(), 1.5);
  EXPECT_EQ(welded[2].x(), 3.0);
}

TEST(WeldWithinTolerance, ZeroToleranceWeldsEqualPositionsOnly) {
  const std::vector<Eigen::Vector3d> vertices = {{0, 0, 0}, {1e-12, 0, 0}, {0, 0, 0}, {5, 5, 5}, {5, 5, 5}};
  std::vector<Eigen::Vector3d> welded;
  EXPECT_EQ(WeldWithinTolerance(vertices, 0.0, WeldDistance::kEuclidean, Eigen::Vector3d::Zero(), 1e-9, &welded),
            (std::vector<int>{0, 1, 0, 2, 2}));
}

// ---------------------------------------------------------------- triangle BVH

// A soup of random triangles in the unit cube (seeded: the same on every
// platform).
TriangleMesh RandomTriangleSoup(std::uint64_t seed, int triangles) {
  Random random(seed);
  TriangleMesh mesh;
  for (int t = 0; t < triangles; ++t) {
    const Eigen::Vector3d corner(random.Uniform01(), random.Uniform01(), random.Uniform01());
    for (int k = 0; k < 3; ++k) {
      mesh.vertices.push_back(
          corner + 0.2 * Eigen::Vector3d(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)));
    }
    mesh.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  return mesh;
}

TEST(TriangleBvh, NearestPointMatchesBruteForceOnARandomSoup) {
  const TriangleMesh mesh = RandomTriangleSoup(20240611, 500);
  const TriangleBvh bvh(mesh.vertices, mesh.triangles);
  ASSERT_EQ(bvh.TriangleCount(), 500);
  Random random(7);
  for (int q = 0; q < 400; ++q) {
    const Eigen::Vector3d p(random.Uniform(-0.5, 1.5), random.Uniform(-0.5, 1.5), random.Uniform(-0.5, 1.5));
    double best = std::numeric_limits<double>::infinity();
    int best_triangle = -1;
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector3d c =
          ClosestPointOnTriangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]],
                                 DegenerateTriangles::kUnguarded, FaceWeights::kTimesReciprocalOfSum);
      const double d2 = (c - p).squaredNorm();
      if (d2 < best) {
        best = d2;
        best_triangle = t;
      }
    }
    const TriangleBvh::Nearest nearest = bvh.NearestPoint(p);
    EXPECT_EQ(nearest.distance_squared, best) << "query " << q;
    EXPECT_EQ(nearest.triangle, best_triangle) << "query " << q;
    EXPECT_EQ((nearest.point - p).squaredNorm(), best) << "query " << q;
    // A hint only starts the bound: the answer is the same.
    const TriangleBvh::Nearest hinted = bvh.NearestPoint(p, (q * 37) % 500);
    EXPECT_EQ(hinted.triangle, nearest.triangle) << "query " << q;
    // Skipping the nearest triangle gives the second nearest.
    const TriangleBvh::Nearest other = bvh.NearestPoint(p, [&](int t) { return t == nearest.triangle; });
    EXPECT_NE(other.triangle, nearest.triangle);
    EXPECT_GE(other.distance_squared, nearest.distance_squared);
  }
}

TEST(TriangleBvh, RayCrossingsOfAClosedBox) {
  const TriangleMesh box = MakeBox({0, 0, 0}, {1, 1, 1});
  const TriangleBvh bvh(box.vertices, box.triangles);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.3, 0.2, 1).normalized();
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, 0.5}, direction, 0), 1);  // from inside: out once
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, -1}, direction, 0), 2);   // from below: in and out
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, 2}, direction, 0), 0);    // from above: away
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, -1}, direction, 0, [](int t) { return t < 2; }), 1);  // z = 0 skipped
  EXPECT_EQ(TriangleBvh().CountCrossings({0, 0, 0}, direction, 0), 0);
  EXPECT_EQ(TriangleBvh().NearestPoint({0, 0, 0}).triangle, -1);
}

}  // namespace
}  // namespace ausbau
