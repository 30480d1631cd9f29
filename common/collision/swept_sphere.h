// A proof that a whole straight motion of D is collision-free, by one cheap
// bound over the volume it sweeps (what makes a long edge through open
// space cost a few queries instead of one check per step).
//
// D lies in a sphere (BoundingSphere). Along the motion Interpolate(a, b, s)
// the sphere's centre c (D's frame) is at t(s) + R(s) c: t linear, R(s) a
// turn about one fixed axis at constant rate. Its distance to the chord from
// a.Apply(c) to b.Apply(c) is at most MaxChordDeviation(a, b, c)
// (geometry/pose.h: |c| min(theta^2 / 8, 2)). So D stays inside the capsule
// around that chord of radius r + that deviation. When no triangle of S
// comes within that radius of the chord (TriangleBvh::AnyWithinSegment,
// exact segment-triangle distances), no pose of the motion has a triangle of
// D touch one of S.
//
// One sphere, not several: covering D by 4, 8 or 16 spheres (each swept
// the same way) proved about as many motions on cubicles, alpha-1.5,
// Twistycool, Home and two L-channel scenes (checks within +-4% of one
// sphere's), at up to that many queries per sweep.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/pose.h"
#include "geometry/triangle_bvh.h"

namespace ausbau {

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
bool SweptSphereClear(const BoundingSphere& sphere, const TriangleBvh& environment, const Pose& a, const Pose& b,
                      double margin);

}  // namespace ausbau
