// What D touches, part by part: at one pose of D, for each part of S (a
// static file today; schemas/scene.md), whether D intersects it and how deep,
// or how far D is from it, and where (a world point on S). A verdict of
// "not removable" names with it the parts that hold D where its best partial
// path ended (workflow/verdict.h), and the disassembly order which parts
// block which (workflow/disassembly_order.h).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

struct PartContact {
  int part = -1;
  std::string name;
  bool intersects = false;  // D's triangles cross the part's
  // Intersecting: the rigid check's depth and depth_exact: the largest over
  // the shell pairs of the shortest translation that separates two convex
  // shells (geometry/shells.h), or of the surface depth of a non-convex
  // pair (collision/mesh_depth.h: how far a point of either surface lies
  // inside the other; to 0.01% of D's diagonal, beyond 1% of it to 1/16 of
  // itself). Where a
  // pair has no depth (two open sheets), the deepest penetration FCL reports
  // over the crossing triangle pairs (how far a triangle's vertex lies
  // beyond the other's plane: a local measure only), not exact.
  double depth = 0;
  bool depth_exact = false;
  double distance = 0;                              // apart: the smallest distance between D and the part
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world: the deepest contact, or the closest point on the part
  // With this part taken away (alone), D comes out along a straight pull
  // from its installed pose under the exact check: the part that stops
  // its motion, not merely one it touches (workflow/verdict.h
  // FindBlockingParts).
  bool frees = false;
};

// `robot`: D's mesh in the frame `pose` places (for a scene: D's vertices
// minus dynamic_origin, and the scene's pose); `environment`: S in the
// world, `part_of_triangle` one part index per triangle of it (empty: one
// part), `names` per part (missing names are written "part <i>"). Returns
// the parts within `reach` of D (distance <= reach or intersecting), the
// intersecting ones first (deepest first), then by distance; with fewer
// than one such part, the nearest part alone. At most `max_parts`.
std::vector<PartContact> MeasurePartContacts(const TriangleMesh& robot, const Pose& pose,
                                             const TriangleMesh& environment, const std::vector<int>& part_of_triangle,
                                             const std::vector<std::string>& names, double reach, int max_parts);

// "cap.stl (intersects, depth 0.3 at [x, y, z])" or "cap.stl (1.2 away,
// closest at [x, y, z])": one line of a report.
std::string DescribePartContact(const PartContact& contact);

}  // namespace ausbau
