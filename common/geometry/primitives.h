// Simple closed meshes built in code, for generated scenes and tests.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/mesh.h"

namespace ausbau {

// Axis-aligned box [min, max], 12 outward-facing triangles.
inline TriangleMesh MakeBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back((i & 1) ? max.x() : min.x(), (i & 2) ? max.y() : min.y(), (i & 4) ? max.z() : min.z());
  }
  // Two counter-clockwise triangles per face, seen from outside.
  mesh.triangles = {{0, 2, 3}, {0, 3, 1},   // z = min
                    {4, 5, 7}, {4, 7, 6},   // z = max
                    {0, 1, 5}, {0, 5, 4},   // y = min
                    {2, 6, 7}, {2, 7, 3},   // y = max
                    {0, 4, 6}, {0, 6, 2},   // x = min
                    {1, 3, 7}, {1, 7, 5}};  // x = max
  return mesh;
}

// A rectangular plate in the xy-plane, z in [z0, z1], outer half-widths
// (ox, oy), with a rectangular through-hole of half-widths (hx, hy) centred at
// (cx, cy). Built from four boxes, so it is a closed (if not merged) solid.
inline TriangleMesh MakePlateWithRectHole(double ox, double oy, double hx, double hy, double cx, double cy, double z0,
                                          double z1) {
  TriangleMesh plate;
  plate.Append(MakeBox({-ox, -oy, z0}, {ox, cy - hy, z1}));           // front strip
  plate.Append(MakeBox({-ox, cy + hy, z0}, {ox, oy, z1}));            // back strip
  plate.Append(MakeBox({-ox, cy - hy, z0}, {cx - hx, cy + hy, z1}));  // left strip
  plate.Append(MakeBox({cx + hx, cy - hy, z0}, {ox, cy + hy, z1}));   // right strip
  return plate;
}

// A square plate with a centred square hole: outer half-width `outer`, hole
// half-width `hole`.
inline TriangleMesh MakePlateWithHole(double outer, double hole, double z0, double z1) {
  return MakePlateWithRectHole(outer, outer, hole, hole, 0, 0, z0, z1);
}

// A closed solid of revolution about the z axis: `profile` is a simple
// polygon in the (r, z) half-plane (r >= 0; corners on the axis, r = 0, are
// shared by all segments), turned in `segments` steps. Outward-facing
// triangles whichever way the profile runs. Caps on posts, rings, bores.
TriangleMesh MakeSolidOfRevolution(const std::vector<Eigen::Vector2d>& profile, int segments);

// A closed prism: the simple polygon `outline` (x, y; either orientation)
// extruded over z in [z0, z1], its ends triangulated by ear clipping.
// L- and U-shaped channels, brackets.
TriangleMesh MakePrism(const std::vector<Eigen::Vector2d>& outline, double z0, double z1);

}  // namespace ausbau
