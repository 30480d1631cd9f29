#include "geometry/closest_point.h"

#include <algorithm>

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

// Writes the weights where asked for; returns the point, so that each region
// below ends in one statement.
Vec3 Answer(const Vec3& point, double wa, double wb, double wc, Vec3* barycentric) {
  if (barycentric != nullptr) *barycentric = Vec3(wa, wb, wc);
  return point;
}

// The point of segment s -> t closest to p, and its parameter u along it.
Vec3 ClosestPointOnSegment(const Vec3& p, const Vec3& s, const Vec3& t, double* u) {
  const Vec3 d = t - s;
  const double length_squared = d.squaredNorm();
  *u = length_squared > 0 ? std::clamp((p - s).dot(d) / length_squared, 0.0, 1.0) : 0.0;
  return s + *u * d;
}

}  // namespace

Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, DegenerateTriangles degenerate,
                            FaceWeights face_weights, Vec3* barycentric) {
  // Guarded edges return the edge's first corner where its length is zero.
  const bool guard_edges = degenerate == DegenerateTriangles::kNearestEdgePoint;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return Answer(a, 1, 0, 0, barycentric);  // vertex a
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return Answer(b, 0, 1, 0, barycentric);  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge ab
    const double denom = d1 - d3;
    if (guard_edges && !(denom > 0)) return Answer(a, 1, 0, 0, barycentric);
    const double v = d1 / denom;
    return Answer(a + v * ab, 1 - v, v, 0, barycentric);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return Answer(c, 0, 0, 1, barycentric);  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge ac
    const double denom = d2 - d6;
    if (guard_edges && !(denom > 0)) return Answer(a, 1, 0, 0, barycentric);
    const double w = d2 / denom;
    return Answer(a + w * ac, 1 - w, 0, w, barycentric);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {  // edge bc
    const double denom = (d4 - d3) + (d5 - d6);
    if (guard_edges && !(denom > 0)) return Answer(b, 0, 1, 0, barycentric);
    const double w = (d4 - d3) / denom;
    return Answer(b + w * (c - b), 0, 1 - w, w, barycentric);
  }
  // The face region. Its weights sum to |ab x ac|^2, which is zero for a
  // collinear triangle and may round to zero or below on a sliver.
  const double sum = va + vb + vc;
  if (!(sum > 0) && degenerate == DegenerateTriangles::kNearestEdgePoint) {
    double u_ab, u_bc, u_ca;
    const Vec3 on_ab = ClosestPointOnSegment(p, a, b, &u_ab);
    const Vec3 on_bc = ClosestPointOnSegment(p, b, c, &u_bc);
    const Vec3 on_ca = ClosestPointOnSegment(p, c, a, &u_ca);
    // The first of equally near edges, in the order ab, bc, ca.
    Vec3 best = on_ab;
    Vec3 weights(1 - u_ab, u_ab, 0);
    if ((on_bc - p).squaredNorm() < (best - p).squaredNorm()) {
      best = on_bc;
      weights = Vec3(0, 1 - u_bc, u_bc);
    }
    if ((on_ca - p).squaredNorm() < (best - p).squaredNorm()) {
      best = on_ca;
      weights = Vec3(u_ca, 0, 1 - u_ca);
    }
    return Answer(best, weights.x(), weights.y(), weights.z(), barycentric);
  }
  if (!(sum > 0) && degenerate == DegenerateTriangles::kNearestCorner) {
    const double da = (p - a).squaredNorm(), db = (p - b).squaredNorm(), dc = (p - c).squaredNorm();
    if (da <= db && da <= dc) return Answer(a, 1, 0, 0, barycentric);
    if (db <= dc) return Answer(b, 0, 1, 0, barycentric);
    return Answer(c, 0, 0, 1, barycentric);
  }
  double v, w;
  if (face_weights == FaceWeights::kDividedBySum) {
    v = vb / sum;
    w = vc / sum;
  } else {
    const double reciprocal = 1.0 / sum;
    v = vb * reciprocal;
    w = vc * reciprocal;
  }
  return Answer(a + ab * v + ac * w, 1 - v - w, v, w, barycentric);
}

}  // namespace ausbau
