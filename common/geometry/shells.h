// A triangle soup split into its shells (connected pieces), and the exact
// penetration depth of two convex shells by the separating-axis theorem.
//
// CAD exports model a part as a soup of closed solids that overlap (a clip
// is a beam box, a hook box and a wedge box glued into a panel box). Each
// solid is one shell here: the triangles connected through shared vertices
// (vertices within a few single-precision steps are welded first, as STL repeats
// them per triangle). A shell that is closed (every edge used by exactly two
// triangles) and lies on one side of each of its triangles' planes is
// convex; for a pair of convex shells the separating-axis test over their
// face normals and the cross products of their feature-edge directions gives
// the exact penetration depth (the shortest translation that separates
// them), the quantity an exact box-box checker measures. Any finer
// tessellation of a convex solid has the same face normals and feature edges
// (coplanar triangles are merged into one direction), so the depth does not
// depend on the tessellation.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <vector>

#include "geometry/mesh.h"

namespace ausbau {

struct Shell {
  std::vector<Eigen::Vector3d> vertices;      // welded, in the mesh's coordinates
  std::vector<std::array<int, 3>> triangles;  // into `vertices`
  std::vector<int> source_triangles;          // index of each triangle in the input mesh
  bool closed = false;                        // every edge shared by exactly two triangles
  bool convex = false;                        // closed, and on one side of every face plane
  // Convex shells only: the corners (vertices where three or more face
  // directions meet; the projections' extremes are always attained there),
  // the distinct face normals and the distinct feature-edge directions
  // (edges between non-coplanar faces), each up to sign.
  std::vector<Eigen::Vector3d> corners;
  std::vector<Eigen::Vector3d> face_normals;
  std::vector<Eigen::Vector3d> edge_directions;
  // Convex shells only: the shell's extent along each face normal, k-th
  // entry for face_normals[k] (min and max of the corners' projections).
  std::vector<double> face_low, face_high;
  Aabb box;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // centre of `box`
  double radius = 0;                                 // max distance of a vertex from `center`
  double volume = 0;                                 // |signed volume| when closed, else 0
  // The mesh's TriangleMesh::cropped_to: within this box no triangle of the
  // shell the mesh was cropped from is missing (empty: an uncropped mesh).
  std::optional<Aabb> complete_within;
};

// Splits `mesh` into shells, in the order of their first triangle. Triangles
// of zero area are kept in their shell but do not count for convexity; a
// triangle two of whose corners weld into one (a sliver thinner than the
// weld) is in no shell (source_triangles leaves it out).
// `stored_magnitude`: how far from the origin the coordinates were when they
// were stored (rounded), where the mesh has been moved since (a planner's
// frame about D's centre); the welding and convexity tolerances follow the
// rounding there. 0: the mesh's own coordinates.
std::vector<Shell> SplitIntoShells(const TriangleMesh& mesh, double stored_magnitude = 0);

// Signed separating-axis depth of two convex shells, A moved by `pose_a`
// (rotation + translation applied to A's vertices), B as it is:
//   > 0: they overlap, and this is the exact penetration depth;
//   <= 0: they are separated (or touch) with a gap of at least -value
//         (a separating axis: a lower bound on their distance).
// `stop_gap` > 0 ends the search at the first axis with a gap larger than it
// (the value is then that gap, negated). Both shells must be convex.
double ConvexSignedDepth(const Shell& a, const Eigen::Isometry3d& pose_a, const Shell& b, double stop_gap = 0.0);

// An upper bound on the largest ConvexSignedDepth over a translation: A at
// pose_a moved by s * move (B's frame) for every s in [0, 1]. Along each
// separating axis u the overlap is min(a_hi - b_lo, b_hi - a_lo), and the
// translation shifts A's interval by s (u . move): the smaller of a rising
// and a falling line, whose largest value over [0, 1] is at their crossing
// (or an end). The depth is the least overlap over the axes at each s, so its
// largest value is at most the least of those maxima. Exact where one axis
// decides throughout (a box sliding on a face: the face normal's overlap
// does not change).
double ConvexSweptDepthBound(const Shell& a, const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& move,
                             const Shell& b);

}  // namespace ausbau
