#include "planning/nearest_neighbors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace ausbau {
namespace {

constexpr int kLeafCapacity = 32;               // a leaf holding more points is split
constexpr int kLeafBuild = 24;                  // largest leaf a (re)build makes
constexpr double kAlpha = 0.72;                 // a child above this share of its parent's points triggers a rebuild
constexpr int kMinRebuild = 4 * kLeafCapacity;  // smaller subtrees are never rebuilt for balance
// Lower bounds are multiplied by this before they prune: it covers the few
// ulps by which the bound and a computed distance may each be off.
constexpr double kShrink = 1.0 - 1e-12;
constexpr double kInf = std::numeric_limits<double>::infinity();

// q and -q are the same rotation: store the one with w > 0 (then x > 0, ...
// on the boundary). Negation is exact, so |q . query| does not change.
void Canonical(const Eigen::Quaterniond& q, double out[4]) {
  const double c[4] = {q.x(), q.y(), q.z(), q.w()};
  bool flip = false;
  for (int i : {3, 0, 1, 2}) {
    if (c[i] != 0) {
      flip = c[i] < 0;
      break;
    }
  }
  for (int i = 0; i < 4; ++i) out[i] = flip ? -c[i] : c[i];
}

// The float next to x towards -inf (RoundDown) or +inf (RoundUp): node boxes
// are stored as floats and must still contain their points.
float RoundDown(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float RoundUp(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// A lower bound on acos(x) for x in [0, 1] (0 above 1): the arc 2 asin(c / 2) over the
// chord c = sqrt(2 (1 - x)), truncated after three terms of its series (all
// terms are positive), so within 1% of acos everywhere on [0, 1].
double AcosLowerBound(double x) {
  const double c2 = std::max(0.0, 2.0 * (1.0 - x));
  return std::sqrt(c2) * (1.0 + c2 * (1.0 / 24.0 + c2 * (3.0 / 640.0)));
}

// Nearest: the best (distance, index) so far.
struct NearestCollector {
  double best = kInf;
  int best_index = -1;
  double bound() const { return best; }
  void Offer(double distance, int index) {
    if (distance < best || (distance == best && index < best_index)) {
      best = distance;
      best_index = index;
    }
  }
};

// KNearest: a max-heap of the k best (distance, index) pairs.
struct KNearestCollector {
  explicit KNearestCollector(std::size_t k) : k(k) { heap.reserve(k); }
  std::size_t k;
  std::vector<std::pair<double, int>> heap;
  double bound() const { return heap.size() < k ? kInf : heap.front().first; }
  void Offer(double distance, int index) {
    const std::pair<double, int> candidate(distance, index);
    if (heap.size() < k) {
      heap.push_back(candidate);
      std::push_heap(heap.begin(), heap.end());
    } else if (candidate < heap.front()) {
      std::pop_heap(heap.begin(), heap.end());
      heap.back() = candidate;
      std::push_heap(heap.begin(), heap.end());
    }
  }
};

// Within: everything up to a fixed radius.
struct WithinCollector {
  double radius;
  std::vector<std::pair<double, int>> found;
  double bound() const { return radius; }
  void Offer(double distance, int index) {
    if (distance <= radius) found.emplace_back(distance, index);
  }
};

std::vector<int> Indices(std::vector<std::pair<double, int>>& pairs) {
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> out;
  out.reserve(pairs.size());
  for (const auto& p : pairs) out.push_back(p.second);
  return out;
}

}  // namespace

struct NearestNeighbors::Query {
  const Pose* pose;
  double t[3];
  double q[4];  // x y z w, as given (the bounds cover both signs)
  double u, one_minus_u;
  double wt, wq;      // u / nu and (1 - u) / pi, for prefilters
  double dot_margin;  // what a computed |dot| may exceed the box bounds by
  double half_norms;  // (|q|^2 + max stored |x|^2) / 2, rounded up
};

NearestNeighbors::Query NearestNeighbors::MakeQuery(const Pose& pose, double u) const {
  Query query;
  query.pose = &pose;
  for (int i = 0; i < 3; ++i) query.t[i] = pose.t[i];
  query.q[0] = pose.q.x(), query.q[1] = pose.q.y(), query.q[2] = pose.q.z(), query.q[3] = pose.q.w();
  query.u = u;
  query.one_minus_u = 1.0 - u;
  query.wt = u / metric_.nu;
  query.wq = (1.0 - u) / M_PI;
  // The corner bound and Eigen's dot of a stored q are sums of four
  // products, each off by at most ~2 eps sum |q_i x_i|; the sphere bound is
  // off by a few eps of |q|^2 + |x|^2. Allow 5x and more.
  const double l1 = std::abs(query.q[0]) + std::abs(query.q[1]) + std::abs(query.q[2]) + std::abs(query.q[3]);
  const double norm2 = pose.q.coeffs().squaredNorm();
  query.dot_margin = 1e-14 * (l1 * max_abs_q_ + norm2 + max_norm2_q_);
  query.half_norms = 0.5 * (norm2 + max_norm2_q_) * (1.0 + 1e-12);
  return query;
}

// ---------------------------------------------------------------- insertion

int NearestNeighbors::NewNode() {
  if (!free_nodes_.empty()) {
    const int node = free_nodes_.back();
    free_nodes_.pop_back();
    nodes_[node] = Node();
    splits_[node] = Split();
    return node;
  }
  nodes_.emplace_back();
  splits_.emplace_back();
  return static_cast<int>(nodes_.size()) - 1;
}

int NearestNeighbors::NewBucket() {
  if (!free_buckets_.empty()) {
    const int bucket = free_buckets_.back();
    free_buckets_.pop_back();
    return bucket;
  }
  const int bucket = static_cast<int>(ids_.size()) / kLeafCapacity;
  coords_.resize(coords_.size() + 7 * kLeafCapacity);
  ids_.resize(ids_.size() + kLeafCapacity);
  return bucket;
}

void NearestNeighbors::Store(int bucket, int slot, const Point& point) {
  double* coords = &coords_[std::size_t(7) * kLeafCapacity * bucket];
  for (int d = 0; d < 7; ++d) coords[d * kLeafCapacity + slot] = point.c[d];
  ids_[std::size_t(kLeafCapacity) * bucket + slot] = point.index;
}

NearestNeighbors::Point NearestNeighbors::Load(int bucket, int slot) const {
  Point point;
  const double* coords = &coords_[std::size_t(7) * kLeafCapacity * bucket];
  for (int d = 0; d < 7; ++d) point.c[d] = coords[d * kLeafCapacity + slot];
  point.index = ids_[std::size_t(kLeafCapacity) * bucket + slot];
  return point;
}

void NearestNeighbors::Add(const Pose& pose) {
  Point point;
  for (int i = 0; i < 3; ++i) point.c[i] = pose.t[i];
  Canonical(pose.q, point.c + 3);
  point.index = static_cast<int>(size_);
  for (int d = 3; d < 7; ++d) max_abs_q_ = std::max(max_abs_q_, std::abs(point.c[d]));
  max_norm2_q_ = std::max(max_norm2_q_, pose.q.coeffs().squaredNorm());
  ++size_;

  if (root_ < 0) {
    root_ = NewNode();
    Build(root_, &point, &point + 1);
    return;
  }
  // Down to a leaf, growing boxes and counts on the way.
  float lo[7], hi[7];
  for (int d = 0; d < 7; ++d) lo[d] = RoundDown(point.c[d]), hi[d] = RoundUp(point.c[d]);
  path_.clear();
  int v = root_;
  while (true) {
    Node& node = nodes_[v];
    for (int d = 0; d < 7; ++d) {
      node.lo[d] = std::min(node.lo[d], lo[d]);
      node.hi[d] = std::max(node.hi[d], hi[d]);
    }
    Split& split = splits_[v];
    ++split.size;
    path_.push_back(v);
    if (node.left < 0) break;
    const double x = point.c[split.dim];
    if (x < split.value) {
      v = node.left;
    } else if (x > split.value) {
      v = node.right;
    } else {
      v = splits_[node.left].size <= splits_[node.right].size ? node.left : node.right;
    }
  }
  // The highest unbalanced node on the path is rebuilt (with the new point).
  for (int w : path_) {
    const Node& node = nodes_[w];
    const int size = splits_[w].size;
    if (node.left < 0 || size < kMinRebuild) break;  // sizes only shrink further down
    const int larger = std::max(splits_[node.left].size, splits_[node.right].size);
    if (larger > kAlpha * size) {
      Rebuild(w, point);
      return;
    }
  }
  Node& leaf = nodes_[path_.back()];
  if (leaf.right < kLeafCapacity) {
    Store(-1 - leaf.left, leaf.right, point);
    ++leaf.right;
  } else {
    Rebuild(path_.back(), point);
  }
}

// Appends the points of the subtree at `node` to scratch_ and frees its
// buckets and nodes (all but `node` itself when keep_node).
void NearestNeighbors::Gather(int node, bool keep_node) {
  const Node& n = nodes_[node];
  if (n.left < 0) {
    const int bucket = -1 - n.left;
    for (int i = 0; i < n.right; ++i) scratch_.push_back(Load(bucket, i));
    free_buckets_.push_back(bucket);
  } else {
    const int left = n.left, right = n.right;
    Gather(left, false);
    Gather(right, false);
  }
  if (!keep_node) free_nodes_.push_back(node);
}

// Rebuilds the subtree at `node` balanced, with `extra`, the point Add is
// inserting (counted in the sizes on path_, stored in no leaf yet).
void NearestNeighbors::Rebuild(int node, const Point& extra) {
  scratch_.clear();
  Gather(node, true);
  scratch_.push_back(extra);
  Build(node, scratch_.data(), scratch_.data() + scratch_.size());  // Build leaves scratch_ alone
}

void NearestNeighbors::Build(int node, Point* begin, Point* end) {
  const int count = static_cast<int>(end - begin);
  double lo[7], hi[7];
  for (int d = 0; d < 7; ++d) lo[d] = kInf, hi[d] = -kInf;
  for (const Point* p = begin; p != end; ++p) {
    for (int d = 0; d < 7; ++d) {
      lo[d] = std::min(lo[d], p->c[d]);
      hi[d] = std::max(hi[d], p->c[d]);
    }
  }
  {
    Node& n = nodes_[node];
    for (int d = 0; d < 7; ++d) n.lo[d] = RoundDown(lo[d]), n.hi[d] = RoundUp(hi[d]);
    splits_[node].size = count;
  }
  if (count <= kLeafBuild) {
    const int bucket = NewBucket();
    for (int i = 0; i < count; ++i) Store(bucket, i, begin[i]);
    nodes_[node].left = -1 - bucket;
    nodes_[node].right = count;
    return;
  }
  // Split the widest coordinate, in metric units: translation over nu,
  // quaternion coordinates over pi (a small chord c is an angle of about
  // c / pi in d'_q).
  int dim = 0;
  double widest = -1;
  for (int d = 0; d < 7; ++d) {
    const double spread = (hi[d] - lo[d]) * (d < 3 ? 1.0 / metric_.nu : 1.0 / M_PI);
    if (spread > widest) widest = spread, dim = d;
  }
  Point* middle = begin + count / 2;
  std::nth_element(begin, middle, end, [dim](const Point& a, const Point& b) {
    return a.c[dim] < b.c[dim] || (a.c[dim] == b.c[dim] && a.index < b.index);
  });
  const int left = NewNode();
  const int right = NewNode();
  nodes_[node].left = left;
  nodes_[node].right = right;
  splits_[node].dim = dim;
  splits_[node].value = middle->c[dim];
  Build(left, begin, middle);
  Build(right, middle, end);
}

// ---------------------------------------------------------------- queries

// A lower bound on d'_c(x, query, u) for every point x in the node's box,
// never above a computed distance (see kShrink and dot_margin). Returns early
// with a value above `bound` when the translation term alone exceeds it.
//
// The rotation term needs an upper bound on |q . x| over the box; two are
// combined:
// * corner: q . x is linear, so over the box it lies between the sums of
//   the per-coordinate min and max of q_i lo_i and q_i hi_i;
// * sphere: q . x = (|q|^2 + |x|^2 - |q - x|^2) / 2 and |q - x| is at least
//   the distance g+ from q to the box (g- from -q for -(q . x)). For points
//   near the query this is far tighter: the box corners stick out of the
//   sphere, which the corner bound counts as closeness.
double NearestNeighbors::LowerBound(const Node& node, const Query& query, double bound) const {
  double gap2 = 0;
  for (int d = 0; d < 3; ++d) {
    const double lo = node.lo[d], hi = node.hi[d];
    const double gap = std::max(0.0, std::max(lo - query.t[d], query.t[d] - hi));
    gap2 += gap * gap;
  }
  const double translation = query.wt * std::sqrt(gap2) * kShrink;
  if (translation > bound) return translation;
  double max_dot = 0, min_dot = 0, plus2 = 0, minus2 = 0;
  for (int d = 0; d < 4; ++d) {
    const double lo = node.lo[3 + d], hi = node.hi[3 + d], q = query.q[d];  // exact float -> double
    const double a = q * lo, b = q * hi;
    max_dot += std::max(a, b);
    min_dot += std::min(a, b);
    const double plus = std::max(0.0, std::max(lo - q, q - hi));    // from q
    const double minus = std::max(0.0, std::max(lo + q, -q - hi));  // from -q
    plus2 += plus * plus;
    minus2 += minus * minus;
  }
  const double sphere = query.half_norms - 0.5 * (1.0 - 1e-12) * std::min(plus2, minus2);
  const double dot = std::min(sphere, std::max(max_dot, -min_dot)) + query.dot_margin;
  return (translation + query.wq * AcosLowerBound(dot)) * kShrink;
}

template <class Collector>
void NearestNeighbors::ScanLeaf(const Node& leaf, const Query& query, Collector& collector) const {
  const int count = leaf.right, bucket = -1 - leaf.left;
  const double* tx = &coords_[std::size_t(7) * kLeafCapacity * bucket];
  const double *ty = tx + kLeafCapacity, *tz = ty + kLeafCapacity;
  const double *qx = tz + kLeafCapacity, *qy = qx + kLeafCapacity, *qz = qy + kLeafCapacity, *qw = qz + kLeafCapacity;
  const int* ids = &ids_[std::size_t(kLeafCapacity) * bucket];
  // Pass 1, branch-free: per point, the squared weighted translation a and
  // the squared weighted chord b of the rotation (|dot| grown by dot_margin,
  // as for the boxes). sqrt(a) + sqrt(b) is a lower bound on d'_c, and it
  // can only be <= bound when a + b <= bound^2: a test without sqrt.
  const double bound2 = collector.bound() * collector.bound() * (1.0 + 1e-9);
  const double wt2 = query.wt * query.wt, wq2 = query.wq * query.wq;
  const double t0 = query.t[0], t1 = query.t[1], t2 = query.t[2];
  const double q0 = query.q[0], q1 = query.q[1], q2 = query.q[2], q3 = query.q[3];
  const double one_minus_margin = 1.0 - query.dot_margin;
  double squared[kLeafCapacity], chord2[kLeafCapacity], cheap2[kLeafCapacity];
  for (int i = 0; i < count; ++i) {
    const double dx = tx[i] - t0, dy = ty[i] - t1, dz = tz[i] - t2;
    const double s = dx * dx + dy * dy + dz * dz;
    const double dot = qx[i] * q0 + qy[i] * q1 + qz[i] * q2 + qw[i] * q3;
    const double c = std::max(0.0, 2.0 * (one_minus_margin - std::abs(dot)));
    squared[i] = s;
    chord2[i] = c;
    cheap2[i] = wt2 * s + wq2 * c;
  }
  const Pose& pose = *query.pose;
  for (int i = 0; i < count; ++i) {
    if (cheap2[i] > bound2) continue;
    const double bound = collector.bound();
    const double cheap = (query.wt * std::sqrt(squared[i]) + query.wq * std::sqrt(chord2[i])) * kShrink;
    if (cheap > bound) continue;
    // From here on, Metric::Distance's own expressions (stored pose first).
    const Eigen::Vector3d t(tx[i], ty[i], tz[i]);
    const double translation = query.u * metric_.Translation(t, pose.t);
    if (translation > bound) continue;  // d'_c >= its translation term, in floating point too
    const Eigen::Quaterniond q(qw[i], qx[i], qy[i], qz[i]);
    const double dot = std::min(1.0, std::abs(q.coeffs().dot(pose.q.coeffs())));
    if ((translation + query.one_minus_u * (AcosLowerBound(dot) / M_PI)) * kShrink > bound) continue;
    collector.Offer(translation + query.one_minus_u * Metric::Rotation(q, pose.q), ids[i]);
  }
}

template <class Collector>
void NearestNeighbors::Search(int v, const Query& query, Collector& collector) const {
  const Node& node = nodes_[v];
  if (node.left < 0) {
    ScanLeaf(node, query, collector);
    return;
  }
  int first = node.left, second = node.right;
  double first_bound = LowerBound(nodes_[first], query, collector.bound());
  double second_bound = LowerBound(nodes_[second], query, collector.bound());
  if (second_bound < first_bound) {
    std::swap(first, second);
    std::swap(first_bound, second_bound);
  }
  if (first_bound <= collector.bound()) Search(first, query, collector);
  if (second_bound <= collector.bound()) Search(second, query, collector);
}

int NearestNeighbors::Nearest(const Pose& query, double u) const {
  if (root_ < 0) return -1;
  const Query q = MakeQuery(query, u);
  NearestCollector collector;
  Search(root_, q, collector);
  return collector.best_index;
}

std::vector<int> NearestNeighbors::Within(const Pose& query, double u, double radius) const {
  if (root_ < 0 || !(radius >= 0)) return {};
  const Query q = MakeQuery(query, u);
  WithinCollector collector{radius, {}};
  if (LowerBound(nodes_[root_], q, radius) <= radius) Search(root_, q, collector);
  return Indices(collector.found);
}

std::vector<int> NearestNeighbors::KNearest(const Pose& query, double u, int k) const {
  if (root_ < 0 || k <= 0) return {};
  const Query q = MakeQuery(query, u);
  KNearestCollector collector(std::min<std::size_t>(static_cast<std::size_t>(k), size_));
  Search(root_, q, collector);
  return Indices(collector.heap);
}

}  // namespace ausbau
