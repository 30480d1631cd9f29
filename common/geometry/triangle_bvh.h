// A bounding volume hierarchy over a triangle mesh's triangles, with exact
// nearest-point, ray-crossing and segment-distance queries (the labeling's
// medial spheres, orientation and exposure tests; the sweeps of
// collision/swept_sphere.h).
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <limits>
#include <vector>

namespace ausbau {

// A bounding volume hierarchy over triangles (binary, median split on the
// widest centroid axis, up to 4 triangles a leaf) with exact queries. The
// triangles should have positive area: the closest-point divisions are not
// guarded, and a degenerate triangle may yield a NaN distance (it is then
// never the nearest).
class TriangleBvh {
 public:
  TriangleBvh() = default;
  TriangleBvh(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, 3>>& triangles);

  struct Nearest {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    double distance_squared = std::numeric_limits<double>::infinity();
    int triangle = -1;
  };
  // The closest point of the mesh to q (exact point-triangle distances).
  // `hint`: a triangle likely to be near (the previous answer) to start the
  // pruning bound from. Ties go to the triangle found first (deterministic).
  Nearest NearestPoint(const Eigen::Vector3d& q, int hint = -1) const;
  // The same over the triangles for which skip(triangle) is false.
  Nearest NearestPoint(const Eigen::Vector3d& q, const std::function<bool(int)>& skip) const;

  // Number of triangles the ray origin + t * direction, t > t_min, crosses;
  // triangles for which skip(triangle) is true are ignored.
  int CountCrossings(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_min,
                     const std::function<bool(int)>& skip = nullptr) const;

  // Calls visit(triangle) for every triangle whose bounding box meets the
  // box [min, max] (touching counts), in the tree's order (deterministic),
  // until visit returns false (the caller has its answer).
  void ForEachTriangleNear(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                           const std::function<bool(int)>& visit) const;

  // Whether some triangle comes within `radius` of the segment [p0, p1]
  // (exact segment-triangle distances; distance <= radius counts). Stops at
  // the first one.
  bool AnyWithinSegment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double radius) const;

  int TriangleCount() const { return static_cast<int>(a_.size()); }

 private:
  struct Node {
    double min[3], max[3];
    int first;  // leaf: first slot in the triangle arrays; inner: index of the left child (right = left + 1)
    int count;  // leaf: number of triangles (> 0); inner: 0
  };
  template <typename Skip>
  Nearest Search(const Eigen::Vector3d& q, Nearest best, const Skip& skip) const;
  void Build(int index, int begin, int end, std::vector<int>& order, const std::vector<Eigen::Vector3d>& centroids);

  std::vector<Node> nodes_;
  std::vector<Eigen::Vector3d> a_, b_, c_;  // triangle corners in leaf order
  std::vector<int> id_;                     // input triangle index in leaf order
  std::vector<int> slot_of_id_;             // input triangle index -> slot
};

}  // namespace ausbau
