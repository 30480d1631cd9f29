// Whether a triangle overlaps an axis-aligned box: the separating-axis test
// of Akenine-Moeller (2001) over 13 axes: the box's three face normals, the
// triangle's normal and the nine cross products of a box axis with a
// triangle edge. Touching counts as overlap.
//
// One implementation for the distance field's octree and the voxelizer's
// surface voxels. Their former copies tested the same axes but rounded the
// projected radii and the triangle's normal differently; `SatRounding` keeps
// each caller's answers bit for bit (they can differ only for a triangle
// that touches the box to within rounding).
#pragma once

#include <Eigen/Core>

namespace ausbau {

enum class SatRounding {
  // Radius on axis n: sum over k of half[k] |n[k]|; the triangle's normal
  // (b - a) x (c - a); an axis of zero radius is tested as any other (the
  // distance field).
  kPerAxisHalfExtent,
  // For a cube (all half extents equal to half[0] = h): radius h * sum over k
  // of |n[k]|; the normal (b - a) x (c - b); an edge axis of zero radius (a
  // zero cross product) is skipped (the voxelizer).
  kCubeHalfSize,
};

// Triangle (a, b, c) against the box of centre `center` and half extents
// `half` (per axis).
bool TriangleOverlapsBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, const Eigen::Vector3d& c, SatRounding rounding);

}  // namespace ausbau
