// A bounding volume hierarchy for the generalized winding number (Jacobson
// et al. 2013) of open or cracked triangle meshes, hierarchical as in
// Barill et al. 2018 ("Fast winding numbers"), and their closest points.
// Used by the voxelizer (inistate/voxel_grid.h) and by the surface depth of
// shells that are not closed (collision/mesh_depth.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/mesh.h"

namespace ausbau {

// A bounding volume hierarchy over (some of) a mesh's triangles: the
// generalized winding number and closest points.
class WindingBvh {
 public:
  // All triangles of `mesh`, or those listed; `flip[t]` (optional, per
  // triangle of the mesh) reverses a triangle's orientation.
  explicit WindingBvh(const TriangleMesh& mesh, const std::vector<int>* triangles = nullptr,
                      const std::vector<bool>* flip = nullptr);

  bool empty() const { return tris_.empty(); }
  // Generalized winding number at p: hierarchical (a BVH node seen from
  // farther than beta times its radius contributes its dipole term).
  double WindingNumber(const Eigen::Vector3d& p, double beta = 2.0) const;
  // The exact sum of signed solid angles / 4 pi (O(n)).
  double WindingNumberExact(const Eigen::Vector3d& p) const;
  // The winding number at p by the hierarchy, and a bound on how far it is
  // from the exact sum. A node's dipole term is off its triangles' exact
  // solid angle by at most 2 A r / (d - r)^3 (A their area, r the node's
  // radius, d its distance: the field of a point source changes by at most
  // 2 / rho^3 per unit length at distance rho); a node whose bound is
  // within `node_error` (winding-number units) counts as its dipole term,
  // others are opened, leaves summed exactly.
  struct Estimate {
    double value = 0;
    double error_bound = 0;  // |value - WindingNumberExact| <= error_bound
  };
  Estimate EstimateWindingNumber(const Eigen::Vector3d& p, double node_error) const;
  // Whether the exact winding number at p is larger than `threshold` in
  // magnitude: by the estimate where its bound decides, else by the exact
  // sum. The bound is loose (errors some 50 times smaller, measured), so the
  // per-node allowance is small: an open shell of 110,000 triangles
  // (CAx-IF's s1 body cut by a crop) then costs about 0.1 ms a query
  // against 5 ms for the exact sum, which decides only near the threshold.
  bool AbsoluteWindingExceeds(const Eigen::Vector3d& p, double threshold, double node_error = 1.0 / 4096) const;

  struct Closest {
    int triangle = -1;            // index into the mesh's triangles
    Eigen::Vector3d point;        // closest point on it
    Eigen::Vector3d barycentric;  // of `point` w.r.t. the triangle's vertices (in mesh order)
    double distance = 0;
  };
  Closest ClosestPoint(const Eigen::Vector3d& p) const;

 private:
  struct Tri {
    Eigen::Vector3d a, b, c;  // as in the mesh
    int id;                   // index into the mesh's triangles
    double sign;              // -1 where the orientation is reversed
  };
  struct Node {
    Aabb box;
    Eigen::Vector3d area_normal = Eigen::Vector3d::Zero();  // sum of the triangles' vector areas
    Eigen::Vector3d center = Eigen::Vector3d::Zero();       // area-weighted centroid
    double radius = 0;                                      // of the ball about center holding the triangles
    double area = 0;                                        // the triangles' area
    int begin = 0, end = 0;                                 // into tris_
    int left = -1, right = -1;                              // children; -1 for a leaf
  };
  // The sum of the triangles' solid angles at p over 4 pi: a node that
  // far(node, distance, distance - radius, error bound of its dipole term
  // in steradians) accepts counts as its dipole term, others are opened.
  template <typename Far>
  Estimate HierarchicalSum(const Eigen::Vector3d& p, const Far& far) const;

  std::vector<Tri> tris_;
  std::vector<Node> nodes_;
};

}  // namespace ausbau
