// A proof that a whole straight motion of D is collision-free, by one cheap
// bound over the volume it sweeps (what makes a long edge through open
// space cost a few queries instead of one check per step).
//
// D lies in a sphere (BoundingSphere). Along the motion Interpolate(a, b, s)
// the sphere's centre c (D's frame) is at t(s) + R(s) c: t linear, R(s) a
// turn about one fixed axis at constant rate through theta =
// RotationAngle(a.q, b.q) <= pi. Its distance to the chord from a.Apply(c)
// to b.Apply(c), at the same s, is that of R(s) c to its own linear
// interpolation, at most s (1 - s) / 2 x max |d^2/ds^2 R(s) c| <= |c|
// theta^2 / 8 (the interpolation error of a C2 curve; and never more than
// 2 |c|). So D stays inside the capsule around that chord of radius r + |c|
// min(theta^2 / 8, 2). When no triangle of S comes within that radius of
// the chord (TriangleTree::AnyWithin, exact segment-triangle distances), no
// pose of the motion has a triangle of D touch one of S.
//
// One sphere, not several: covering D by 4, 8 or 16 spheres (each swept
// the same way) proved about as many motions on cubicles, alpha-1.5,
// Twistycool, Home and two L-channel scenes (checks within +-4% of one
// sphere's), at up to that many queries per sweep.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "geometry/pose.h"

namespace ausbau {

// Squared distance between the segment [p0, p1] and the triangle (a, b, c);
// 0 when they meet. Degenerate triangles (a segment or a point) and
// segments (a point) are handled.
double SegmentTriangleDistanceSquared(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& a,
                                      const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// An AABB tree over a mesh's triangles (world coordinates) that answers
// whether any triangle comes within a distance of a segment.
class TriangleTree {
 public:
  explicit TriangleTree(std::vector<std::array<Eigen::Vector3d, 3>> triangles);
  // True when some triangle is within `radius` of the segment [p0, p1]
  // (distance <= radius). Thread-safe.
  bool AnyWithin(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double radius) const;

 private:
  struct Node {
    Eigen::Vector3d min, max;
    int first = 0, count = 0;  // a leaf's triangles: triangles_[first, first + count)
    int left = -1, right = -1;
  };
  int Build(int first, int count);

  std::vector<std::array<Eigen::Vector3d, 3>> triangles_;  // in leaf order (Build sorts them)
  std::vector<Node> nodes_;
};

// The sphere about the centre of D's box (D's frame, about its reference
// point) that holds all of D's vertices, so all its triangles.
struct BoundingSphere {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 0;
  static BoundingSphere Of(const std::vector<Eigen::Vector3d>& vertices);
};

// Whether the straight motion a -> b of D (inside `sphere`) keeps every
// triangle of D off every triangle in `environment` (see the top of this
// file). `margin` is added to the capsule's radius, so that poses in which
// D and S come within it are not proved free either.
bool SweptSphereClear(const BoundingSphere& sphere, const TriangleTree& environment, const Pose& a, const Pose& b,
                      double margin);

}  // namespace ausbau
