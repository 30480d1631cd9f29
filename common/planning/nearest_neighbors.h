// Exact nearest neighbours under the thesis metric d'_c with a weight u that
// may change from query to query (CR-RRTC draws a new u per extension).
//
// A dynamic kd-tree over R^3 x S^3 in the spirit of Yershova & LaValle 2007
// ("Improving motion-planning algorithms by efficient nearest-neighbor
// searching"): every pose is a point of R^7 (t, then q in Eigen's coefficient
// order x y z w, flipped to the hemisphere w >= 0; q and -q are the same
// rotation). Every node keeps the tight bounding box of its points. Because u
// is only known at query time, a node's lower bound combines the two terms,
// each bounded on its own:
//
//   d'_c >= u/nu * dist(t_query, translation box)
//         + (1-u)/pi * acos(min(1, upper bound of |q_query . x| over the quaternion box))
//
// The |dot| bound covers q and -q and is the smaller of the corner bound (q . x
// is linear in x) and a sphere bound (q . x = (|q|^2 + |x|^2 - |q - x|^2) / 2
// with |q - x| at least the distance from q, or -q, to the box), which is far
// tighter for boxes near the query. acos is bounded from below by a truncated
// series of the chord, so a node costs no transcendental. Search is depth
// first, nearer child (by bound) first, pruning a child whose bound exceeds
// the best distance so far.
//
// Leaves hold up to kLeafCapacity points coordinate by coordinate; a leaf
// scan first computes, for all its points at once (vectorizable), a cheap
// lower bound from the squared translation and the chord of the rotation, and
// evaluates the exact distance only for the few points it does not rule out;
// there, as in the old linear scan, the weighted translation is compared
// before the acos.
//
// Exactness: a candidate's distance is computed with the very expressions of
// Metric::Distance (stored pose first, query second) and candidates are
// ordered by (distance, index), so results equal a brute-force scan with
// Metric::Distance bit for bit, ties to the lower index included. Bounds
// only prune when they exceed the best distance strictly, and are made safe
// against rounding: boxes are rounded outwards (they are stored as floats),
// bounds are shrunk by a relative 1e-12 and the |dot| bounds grown by a few
// ulps (the tests fail without these margins).
//
// Growth: a point goes down the tree (by the split planes) into a leaf; a
// full leaf is split at the median of its widest coordinate (translation
// spreads over nu, quaternion spreads over pi), and the highest subtree on
// the path whose larger child holds more than kAlpha of its points is
// rebuilt balanced (scapegoat style), so depth stays O(log n) and insertion
// O(log^2 n) amortized for any insertion order (planner trees grow outwards).
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
