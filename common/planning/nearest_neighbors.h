// Exact nearest neighbours under the thesis metric d'_c with a weight u that
// may change from query to query (CR-RRTC draws a new u per extension).
//
// A dynamic kd-tree over R^3 x S^3 in the spirit of Yershova & LaValle 2007
// ("Improving motion-planning algorithms by efficient nearest-neighbor
// searching"): every pose is a point of R^7 (t, then q in Eigen's coefficient
// order x y z w, flipped to the hemisphere w >= 0; q and -q are the same
// rotation). Nodes keep the tight bounding box of their points. Because u is
// only known at query time, a node's lower bound is built from the two terms
// separately:
//
//   d'_c >= u/nu * dist(t_query, translation box)
//         + (1-u)/pi * acos(min(1, max over the quaternion box of |q_query . x|))
//
// where the max of |dot| covers both q and -q (max(max dot, -min dot), each
// from the box corners) and acos is bounded from below by a truncated series
// of the chord, so no transcendental is evaluated per node. Bounds are shrunk
// by a tiny relative margin (and the dot bound grown by a few ulps) so that
// rounding can never prune a point whose computed distance ties the best one.
//
// Exactness: every candidate's distance is computed with the very expression
// of Metric::Distance (stored pose first, query second), and candidates are
// ordered by (distance, index). Results are identical, bit for bit and with
// ties to the lower index, to a brute-force scan with Metric::Distance.
//
// Growth: a point is inserted down the tree into a leaf bucket (capacity
// kLeafCapacity); a full leaf is split at the median of its widest coordinate
// (translation spreads scaled by 1/nu, quaternion spreads by 1/pi), and a
// subtree whose larger child holds more than kAlpha of its points is rebuilt
// balanced (scapegoat style), so the depth stays O(log n) and insertion is
// O(log^2 n) amortized whatever the insertion order (planner trees grow
// outwards, which would degrade a tree that is never rebalanced).
//
// Queries allocate nothing (Nearest) or only their result (Within,
// KNearest), use no shared mutable state and may run concurrently; Add must
// not run concurrently with anything.
#pragma once

#include <cstddef>
#include <vector>

#include "planning/state_space.h"

namespace ausbau {

class NearestNeighbors {
 public:
  explicit NearestNeighbors(const Metric& metric) : metric_(metric) {}

  // The pose gets the index size() (insertion order).
  void Add(const Pose& pose);
  std::size_t size() const { return size_; }

  // Index of the nearest stored pose under d'_c(., query, u) (-1 when
  // empty). Ties go to the lower index.
  int Nearest(const Pose& query, double u) const;
  // All indices with d'_c <= radius, by increasing distance (ties by index).
  std::vector<int> Within(const Pose& query, double u, double radius) const;
  // The min(k, size()) nearest, by increasing distance (ties by index).
  std::vector<int> KNearest(const Pose& query, double u, int k) const;

 private:
  struct Point {
    double c[7];  // t x y z, q x y z w with q canonical (see Canonical)
    int index;
  };
  // What queries read of a node, one cache line: its box (tight, rounded
  // outwards to float) and its children.
  struct alignas(64) Node {
    float lo[7], hi[7];  // t x y z, q x y z w
    int left = -1;       // >= 0: the left child; < 0: a leaf with bucket -1 - left
    int right = 0;       // an inner node: the right child; a leaf: its number of points
  };
  // What only insertion reads.
  struct Split {
    int size = 0;  // points in the subtree
    int dim = 0;
    double value = 0;
  };
  struct Query;
  template <class Collector>
  void Search(int node, const Query& query, Collector& collector) const;
  template <class Collector>
  void ScanLeaf(const Node& leaf, const Query& query, Collector& collector) const;
  double LowerBound(const Node& node, const Query& query, double bound) const;
  Query MakeQuery(const Pose& pose, double u) const;

  int NewNode();
  int NewBucket();
  void Store(int bucket, int slot, const Point& point);
  Point Load(int bucket, int slot) const;
  void Rebuild(int node, const Point& extra);
  void Gather(int node, bool keep_node);
  void Build(int node, Point* begin, Point* end);

  Metric metric_;
  std::size_t size_ = 0;
  double max_abs_q_ = 0;    // largest |coefficient| of a stored quaternion
  double max_norm2_q_ = 0;  // largest squared norm of a stored quaternion
  int root_ = -1;
  std::vector<Node> nodes_;
  std::vector<Split> splits_;  // by node
  // Leaf buckets of kLeafCapacity points, coordinate by coordinate
  // (bucket b, dimension d, slot i: coords_[(7 b + d) kLeafCapacity + i]).
  std::vector<double> coords_;
  std::vector<int> ids_;  // bucket b, slot i: ids_[b kLeafCapacity + i]
  std::vector<int> free_nodes_, free_buckets_;
  std::vector<int> path_;       // scratch for Add
  std::vector<Point> scratch_;  // scratch for rebuilds
};

}  // namespace ausbau
