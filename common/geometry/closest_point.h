// The closest point on a triangle to a point (Ericson, Real-Time Collision
// Detection, 5.1.5: tests of the Voronoi regions of the three vertices, the
// three edges and the face, in barycentric terms); and the distance between
// a segment and a triangle (the sweeps of collision/swept_sphere.h).
//
// One implementation for the distance field, the labeling BVH and the
// voxelizer. They used to carry their own copies, which agree on every
// proper triangle's region but differ where a test divides by zero (a
// triangle with coincident corners or, by rounding, no area) and in how the
// face weights are rounded; the two parameters below keep each caller's
// results bit for bit.
#pragma once

#include <Eigen/Core>

namespace ausbau {

// What the query does where Ericson's tests would divide by zero (an edge of
// zero length) or by a sum of face weights that is zero or, by rounding on a
// sliver, negative.
enum class DegenerateTriangles {
  // Divide as Ericson does: such a triangle yields NaN or infinity. For
  // callers that have removed degenerate triangles (the labeling topology).
  kUnguarded,
  // An edge of zero length yields its first corner; a triangle without area
  // the nearest point of its three edges (the distance field).
  kNearestEdgePoint,
  // Edges as kUnguarded; a triangle without area yields its nearest corner
  // (the first of equally near ones, in the order a, b, c; the voxelizer).
  kNearestCorner,
};

// How the barycentric weights of a point in the face region are rounded:
// (vb, vc) x (1 / sum), or (vb, vc) / sum. Equal up to the last bit.
enum class FaceWeights {
  kTimesReciprocalOfSum,
  kDividedBySum,
};

// The point of triangle (a, b, c) closest to p. `barycentric` (optional)
// receives the weights of a, b and c of the returned point.
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c, DegenerateTriangles degenerate,
                                       FaceWeights face_weights, Eigen::Vector3d* barycentric = nullptr);

// Squared distance between the segment [p0, p1] and the triangle (a, b, c);
// 0 when they meet. Degenerate triangles (a segment or a point) and
// segments (a point) are handled: no division by zero.
double SegmentTriangleDistanceSquared(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& a,
                                      const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace ausbau
