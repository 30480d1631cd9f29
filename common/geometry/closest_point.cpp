#include "geometry/closest_point.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>

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

double PointSegmentDistanceSquared(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).squaredNorm();
}

// Ericson, Real-Time Collision Detection 5.1.9, with both degenerate cases.
double SegmentSegmentDistanceSquared(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  if (a <= 0 && e <= 0) return r.squaredNorm();
  if (a <= 0) return PointSegmentDistanceSquared(p1, p2, q2);
  if (e <= 0) return PointSegmentDistanceSquared(p2, p1, q1);
  const double c = d1.dot(r), b = d1.dot(d2), denominator = a * e - b * b;
  double s = denominator > 0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return (p1 + s * d1 - (p2 + t * d2)).squaredNorm();
}

// Distance from p to the plane region of a non-degenerate triangle, when
// p projects inside it (else +infinity: then an edge is nearer).
double PointInsideTriangleDistanceSquared(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                          const Vec3& normal) {
  // Inside when p's projection lies on the inner side of all three edges.
  if ((b - a).cross(p - a).dot(normal) < 0 || (c - b).cross(p - b).dot(normal) < 0 ||
      (a - c).cross(p - c).dot(normal) < 0) {
    return std::numeric_limits<double>::infinity();
  }
  const double height = (p - a).dot(normal);
  return height * height / normal.squaredNorm();
}

// Whether the segment crosses the triangle's plane inside the triangle
// (not parallel to it; a parallel segment is left to the edge distances).
// Tolerant on the side of "crosses".
bool SegmentCrossesTriangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c,
                            const Vec3& normal) {
  const double h0 = (p0 - a).dot(normal), h1 = (p1 - a).dot(normal);
  if ((h0 > 0 && h1 > 0) || (h0 < 0 && h1 < 0) || h0 == h1) return false;
  const Vec3 x = p0 + (h0 / (h0 - h1)) * (p1 - p0);
  const double slack = -1e-12 * normal.squaredNorm();
  return (b - a).cross(x - a).dot(normal) >= slack && (c - b).cross(x - b).dot(normal) >= slack &&
         (a - c).cross(x - c).dot(normal) >= slack;
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

double SegmentTriangleDistanceSquared(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Where segment and triangle do not meet, the nearest pair has an end of
  // the segment or a point of the triangle's boundary: if both were inner
  // points, the line between them would be normal to the plane and to the
  // segment, so the segment would be parallel to the plane and could slide
  // to one of those.
  double best = std::min({SegmentSegmentDistanceSquared(p0, p1, a, b), SegmentSegmentDistanceSquared(p0, p1, b, c),
                          SegmentSegmentDistanceSquared(p0, p1, c, a)});
  const Vec3 normal = (b - a).cross(c - a);
  const double scale2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  if (normal.squaredNorm() <= 1e-24 * scale2 * scale2) return best;  // degenerate: its edges are all of it
  if (SegmentCrossesTriangle(p0, p1, a, b, c, normal)) return 0;
  best = std::min(best, PointInsideTriangleDistanceSquared(p0, a, b, c, normal));
  return std::min(best, PointInsideTriangleDistanceSquared(p1, a, b, c, normal));
}

}  // namespace ausbau
