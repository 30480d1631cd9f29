#include "collision/distance_field.h"

#include <unistd.h>

#include <omp.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "artifact/artifact.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/log.h"
#include "geometry/closest_point.h"
#include "geometry/triangle_box.h"
#include "geometry/weld.h"

namespace ausbau {

// Builds a DistanceField; a class so that it may fill the field's private
// members (friend of DistanceField).
class DistanceFieldBuilder {
 public:
  DistanceFieldBuilder(const TriangleMesh& mesh, const DistanceFieldOptions& options);
  std::shared_ptr<DistanceField> Build();

 private:
  using Vec3 = Eigen::Vector3d;

  void BuildSurfaceCells();  // octree -> slot_, list_begin_, list_tris_
  // The triangles the votes use: duplicates removed, consistently oriented.
  // *closed: every edge shared by exactly two of them, consistently
  // oriented; then the votes count winding numbers, else parities.
  std::vector<std::array<Vec3, 3>> OrientedTriangles(bool* closed) const;
  void ComputeVotes();  // six-ray winding votes -> vote_
  void MarkBand();      // dilation of the surface cells -> band_
  void ComputeBand();   // exact nearest points in the band
  void Propagate();     // separable sweeps + refinement for far cells
  void Classify();

  Vec3 Center(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return origin_ + h_ * Vec3(x + 0.5, y + 0.5, z + 0.5);
  }
  std::int64_t Index(std::int64_t x, std::int64_t y, std::int64_t z) const { return x + nx_ * (y + ny_ * z); }
  void Report(double fraction);

  const TriangleMesh& mesh_;
  DistanceFieldOptions options_;
  int threads_ = 1;
  std::shared_ptr<DistanceField> field_;
  Vec3 origin_;
  double h_ = 1;
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0, n_ = 0;
  std::vector<std::array<Vec3, 3>> tri_;  // triangle corners, contiguous
  std::vector<std::int32_t> slot_;        // surface cell -> its list, -1 otherwise
  std::vector<std::int64_t> list_begin_;  // CSR over surface cells
  std::vector<std::int32_t> list_tris_;
  std::vector<std::int16_t> vote_;  // sum of the six ray winding numbers
  std::vector<std::uint8_t> band_;  // 1 = surface band (exact nearest point)
  bool winding_ = true;             // votes are winding numbers (closed, oriented) or parities
};

namespace {

using Vec3 = Eigen::Vector3d;

constexpr int kAlgorithmVersion = 1;

// The field's geometric kernels as its recorded results were computed with
// (geometry/closest_point.h, geometry/triangle_box.h): degenerate triangles
// of the input are kept, so the closest point guards its divisions.
constexpr DegenerateTriangles kDegenerate = DegenerateTriangles::kNearestEdgePoint;
constexpr FaceWeights kFaceWeights = FaceWeights::kTimesReciprocalOfSum;
constexpr SatRounding kOctreeRounding = SatRounding::kPerAxisHalfExtent;

int ThreadCount(int requested) { return requested > 0 ? requested : std::max(1, omp_get_max_threads()); }

// 2D helpers for the scanline crossings (top-left rule on canonically
// ordered edges: a line through a shared edge or vertex is counted once).
struct P2 {
  double u, v;
};
bool Less(const P2& a, const P2& b) { return a.u < b.u || (a.u == b.u && a.v < b.v); }
double Orient(const P2& x, const P2& y, const P2& p) { return (y.u - x.u) * (p.v - x.v) - (y.v - x.v) * (p.u - x.u); }
// Exactly antisymmetric in (x, y): the value is computed from the
// canonically ordered pair and negated when swapped.
double EdgeFunction(const P2& x, const P2& y, const P2& p) { return Less(x, y) ? Orient(x, y, p) : -Orient(y, x, p); }
bool OwnsEdge(const P2& x, const P2& y) {
  const double du = y.u - x.u, dv = y.v - x.v;
  return dv < 0 || (dv == 0 && du > 0);
}
// a, b, c counter-clockwise.
bool InsideTopLeft(const P2& a, const P2& b, const P2& c, const P2& p) {
  const P2* e[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
  for (auto& edge : e) {
    const double value = EdgeFunction(*edge[0], *edge[1], p);
    if (value < 0) return false;
    if (value == 0 && !OwnsEdge(*edge[0], *edge[1])) return false;
  }
  return true;
}

std::string FormatDouble(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

std::string FormatGiB(std::uint64_t bytes) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.2f GiB", static_cast<double>(bytes) / (1024.0 * 1024.0 * 1024.0));
  return buffer;
}

}  // namespace

// ---------------------------------------------------------------------------
// Content hash

std::string MeshContentHash(const TriangleMesh& mesh) {
  Hasher hasher;
  hasher.Add(std::string_view("ausbau-mesh/1"));
  const std::uint64_t counts[2] = {mesh.vertices.size(), mesh.triangles.size()};
  hasher.Add(counts, sizeof counts);
  for (const auto& v : mesh.vertices) {
    const double xyz[3] = {v.x(), v.y(), v.z()};
    hasher.Add(xyz, sizeof xyz);
  }
  for (const auto& t : mesh.triangles) {
    const std::int32_t ijk[3] = {t[0], t[1], t[2]};
    hasher.Add(ijk, sizeof ijk);
  }
  return hasher.HexDigest();
}

// ---------------------------------------------------------------------------
// Options, plan, memory guard

void DistanceFieldOptions::Check() const {
  if (resolution < 2 || resolution > kMaxDistanceFieldResolution) {
    throw OptionError(&resolution, "field_cells",
                      "distance field resolution must lie in [2, " + std::to_string(kMaxDistanceFieldResolution) +
                          "] (got " + std::to_string(resolution) + ")");
  }
  if (threads < 0) throw OptionError(&threads, "threads", "must be >= 0");
  if (!(padding >= 1.0 && padding <= 4.0)) throw OptionError(&padding, "padding", "must lie in [1, 4]");
  if (memory_budget_bytes == 0) throw OptionError(&memory_budget_bytes, "memory_budget_bytes", "must be positive");
}

// Bytes per cell at the peak of construction: the cells (16) and classes
// (1) kept, the surface slot (4), ray buckets (4), votes (2) and band flags
// (2) that are freed at the end.
constexpr std::uint64_t kBuildBytesPerCell = 16 + 1 + 4 + 4 + 2 + 2;

DistanceFieldPlan PlanDistanceField(const TriangleMesh& mesh, const DistanceFieldOptions& options) {
  options.Check();
  if (mesh.triangles.empty() || mesh.vertices.empty()) throw InputError("distance field: the mesh has no triangles");
  const Aabb box = mesh.Bounds();
  if (!box.min.allFinite() || !box.max.allFinite())
    throw InputError("distance field: the mesh has non-finite vertices");
  const Vec3 size = box.Size();
  double longest = size.maxCoeff();
  if (!(longest > 0)) longest = std::max(1e-6, 1e-6 * box.max.cwiseAbs().maxCoeff());
  DistanceFieldPlan plan;
  plan.spacing = options.padding * longest / options.resolution;
  const int min_cells = std::min(options.resolution, 4);
  for (int k = 0; k < 3; ++k) {
    const double cells = std::ceil(options.padding * size[k] / plan.spacing - 1e-9);
    plan.dims[k] = std::clamp(static_cast<int>(cells), min_cells, options.resolution);
  }
  plan.origin = box.Center() - 0.5 * plan.spacing * Vec3(plan.dims[0], plan.dims[1], plan.dims[2]);
  plan.cells = static_cast<std::uint64_t>(plan.dims[0]) * plan.dims[1] * plan.dims[2];
  // Triangle lists of the surface cells: a rough bound of 4 entries per
  // triangle plus one per surface cell, which itself is at most all cells.
  plan.bytes = plan.cells * kBuildBytesPerCell + mesh.triangles.size() * (72 + 16);
  if (plan.bytes > options.memory_budget_bytes) {
    throw InputError("distance field: resolution " + std::to_string(options.resolution) + " (" +
                     std::to_string(plan.dims[0]) + " x " + std::to_string(plan.dims[1]) + " x " +
                     std::to_string(plan.dims[2]) + " cells) needs about " + FormatGiB(plan.bytes) +
                     ", more than the memory budget of " + FormatGiB(options.memory_budget_bytes) +
                     " (lower the resolution or raise the budget)");
  }
  return plan;
}

// ---------------------------------------------------------------------------
// DistanceField

std::int64_t DistanceField::Locate(const Eigen::Vector3d& p) const {
  const auto c = LocateCell(p);
  return Index(c[0], c[1], c[2]);
}

std::array<int, 3> DistanceField::LocateCell(const Eigen::Vector3d& p) const {
  std::array<int, 3> c{};
  for (int k = 0; k < 3; ++k) {
    double f = std::floor((p[k] - origin_[k]) / spacing_);
    if (!(f >= 0)) f = 0;  // also NaN
    c[k] = static_cast<int>(std::min(f, static_cast<double>(dims_[k] - 1)));
  }
  return c;
}

// ---------------------------------------------------------------------------
// Construction

DistanceFieldBuilder::DistanceFieldBuilder(const TriangleMesh& mesh, const DistanceFieldOptions& options)
    : mesh_(mesh), options_(options) {}

// Between the build's steps: the progress, and the place to stop when
// cancelled (the steps' parallel loops must not throw).
void DistanceFieldBuilder::Report(double fraction) {
  ThrowIfCancelled();
  if (options_.progress) options_.progress(static_cast<std::int64_t>(1000 * std::clamp(fraction, 0.0, 1.0)), 1000);
}

std::shared_ptr<DistanceField> DistanceFieldBuilder::Build() {
  const DistanceFieldPlan plan = PlanDistanceField(mesh_, options_);
  threads_ = ThreadCount(options_.threads);
  for (const auto& t : mesh_.triangles) {
    for (int i : t) {
      if (i < 0 || static_cast<std::size_t>(i) >= mesh_.vertices.size()) {
        throw InputError("distance field: triangle index out of range");
      }
    }
  }
  if (mesh_.triangles.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw InputError("distance field: more than 2^31 triangles");
  }
  field_ = std::make_shared<DistanceField>();
  field_->origin_ = plan.origin;
  field_->spacing_ = plan.spacing;
  field_->dims_ = plan.dims;
  field_->resolution_ = options_.resolution;
  field_->padding_ = options_.padding;
  field_->mesh_hash_ = MeshContentHash(mesh_);
  field_->triangle_count_ = static_cast<std::int64_t>(mesh_.triangles.size());
  origin_ = plan.origin;
  h_ = plan.spacing;
  nx_ = plan.dims[0];
  ny_ = plan.dims[1];
  nz_ = plan.dims[2];
  n_ = nx_ * ny_ * nz_;
  tri_.resize(mesh_.triangles.size());
  for (std::size_t i = 0; i < mesh_.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) tri_[i][k] = mesh_.vertices[mesh_.triangles[i][k]];
  }

  auto clock = std::chrono::steady_clock::now();
  auto lap = [&clock](const char* phase) {
    const auto now = std::chrono::steady_clock::now();
    LogDebug("distance field: %s %.3f s", phase, std::chrono::duration<double>(now - clock).count());
    clock = now;
  };
  BuildSurfaceCells();
  lap("octree (surface cells)");
  Report(0.25);
  ComputeVotes();
  lap("inside/outside votes");
  Report(0.35);
  MarkBand();
  ComputeBand();
  lap("surface band");
  Report(0.75);
  Propagate();
  lap("propagation");
  Report(0.95);
  Classify();
  Report(1.0);
  LogDebug("distance field: %zu surface cells, %zu triangle references", list_begin_.size() - 1, list_tris_.size());
  return field_;
}

void DistanceFieldBuilder::BuildSurfaceCells() {
  struct Node {
    int x, y, z;
    std::int64_t begin;
    std::int32_t count;
  };
  int size = 1;
  while (size < std::max({nx_, ny_, nz_})) size *= 2;
  std::vector<Node> nodes{{0, 0, 0, 0, static_cast<std::int32_t>(tri_.size())}};
  std::vector<std::int32_t> lists(tri_.size());
  for (std::size_t i = 0; i < tri_.size(); ++i) lists[i] = static_cast<std::int32_t>(i);
  const double eps = 1e-6 * h_;

  slot_.assign(n_, -1);
  while (size > 1) {
    const int half = size / 2;
    const bool leaves = half == 1;
    std::vector<std::vector<Node>> next_nodes(threads_);
    std::vector<std::vector<std::int32_t>> next_lists(threads_);
#pragma omp parallel num_threads(threads_)
    {
      const int me = omp_get_thread_num();
      auto& my_nodes = next_nodes[me];
      auto& my_lists = next_lists[me];
#pragma omp for schedule(dynamic, 4)
      for (std::int64_t i = 0; i < static_cast<std::int64_t>(nodes.size()); ++i) {
        const Node node = nodes[i];
        for (int c = 0; c < 8; ++c) {
          const int cx = node.x + ((c & 1) ? half : 0), cy = node.y + ((c & 2) ? half : 0),
                    cz = node.z + ((c & 4) ? half : 0);
          if (cx >= nx_ || cy >= ny_ || cz >= nz_) continue;
          const Vec3 lo = origin_ + h_ * Vec3(cx, cy, cz);
          const Vec3 half_extent = Vec3::Constant(0.5 * h_ * half + eps);
          const Vec3 center = lo + Vec3::Constant(0.5 * h_ * half);
          const std::int64_t begin = static_cast<std::int64_t>(my_lists.size());
          for (std::int32_t k = 0; k < node.count; ++k) {
            const std::int32_t t = lists[node.begin + k];
            if (TriangleOverlapsBox(center, half_extent, tri_[t][0], tri_[t][1], tri_[t][2], kOctreeRounding)) {
              my_lists.push_back(t);
            }
          }
          const auto count = static_cast<std::int32_t>(static_cast<std::int64_t>(my_lists.size()) - begin);
          if (count > 0) my_nodes.push_back({cx, cy, cz, begin, count});
        }
      }
    }
    // Concatenate the per-thread results (lists keep ascending triangle order).
    std::size_t total_nodes = 0, total_lists = 0;
    for (int t = 0; t < threads_; ++t) total_nodes += next_nodes[t].size(), total_lists += next_lists[t].size();
    std::vector<Node> merged_nodes;
    std::vector<std::int32_t> merged_lists;
    merged_nodes.reserve(total_nodes);
    merged_lists.reserve(total_lists);
    for (int t = 0; t < threads_; ++t) {
      const std::int64_t offset = static_cast<std::int64_t>(merged_lists.size());
      for (Node node : next_nodes[t]) {
        node.begin += offset;
        merged_nodes.push_back(node);
      }
      merged_lists.insert(merged_lists.end(), next_lists[t].begin(), next_lists[t].end());
      std::vector<Node>().swap(next_nodes[t]);
      std::vector<std::int32_t>().swap(next_lists[t]);
    }
    nodes.swap(merged_nodes);
    lists.swap(merged_lists);
    size = half;
    if (leaves) break;
  }
  // Leaves (single cells): sort by cell index so that the CSR layout does not
  // depend on the thread count.
  if (size != 1) {
    // A one-cell grid cannot happen (at least 2 cells per axis), but keep
    // the invariant: nodes are cells here.
    throw std::logic_error("distance field: octree did not reach the cell level");
  }
  std::sort(nodes.begin(), nodes.end(),
            [this](const Node& a, const Node& b) { return Index(a.x, a.y, a.z) < Index(b.x, b.y, b.z); });
  list_begin_.resize(nodes.size() + 1);
  list_tris_.clear();
  list_tris_.reserve(lists.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    list_begin_[i] = static_cast<std::int64_t>(list_tris_.size());
    list_tris_.insert(list_tris_.end(), lists.begin() + nodes[i].begin,
                      lists.begin() + nodes[i].begin + nodes[i].count);
    slot_[Index(nodes[i].x, nodes[i].y, nodes[i].z)] = static_cast<std::int32_t>(i);
  }
  list_begin_[nodes.size()] = static_cast<std::int64_t>(list_tris_.size());
}

std::vector<std::array<Vec3, 3>> DistanceFieldBuilder::OrientedTriangles(bool* closed) const {
  // Vertices merged by exact position.
  const std::vector<int> merged = WeldExactPositions(mesh_.vertices);
  // Unique triangles (the same three positions in any order count once:
  // double-sided exports and duplicates), degenerate ones dropped.
  struct Tri {
    std::array<int, 3> v;
    std::int32_t source;
  };
  std::vector<Tri> tris;
  tris.reserve(mesh_.triangles.size());
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& src = mesh_.triangles[t];
    const std::array<int, 3> v = {merged[src[0]], merged[src[1]], merged[src[2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
    tris.push_back({v, static_cast<std::int32_t>(t)});
  }
  std::vector<std::pair<std::array<int, 3>, int>> keys(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    std::array<int, 3> k = tris[i].v;
    std::sort(k.begin(), k.end());
    keys[i] = {k, static_cast<int>(i)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> keep(tris.size(), 0);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i == 0 || keys[i].first != keys[i - 1].first) keep[keys[i].second] = 1;
  }
  std::vector<Tri> unique;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    if (keep[i]) unique.push_back(tris[i]);
  }
  // Consistent orientation across manifold edges (shared by exactly two
  // triangles), breadth first per connected component; then each component
  // is turned so that its signed volume is positive.
  struct EdgeUse {
    std::uint64_t key;
    int tri;
    bool forward;  // traversed from the smaller to the larger vertex id
  };
  std::vector<EdgeUse> uses;
  uses.reserve(unique.size() * 3);
  for (std::size_t t = 0; t < unique.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = unique[t].v[k], b = unique[t].v[(k + 1) % 3];
      const std::uint64_t key =
          (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
      uses.push_back({key, static_cast<int>(t), a < b});
    }
  }
  std::sort(uses.begin(), uses.end(),
            [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key || (x.key == y.key && x.tri < y.tri); });
  // neighbours[t]: (other triangle, same traversal direction?) over manifold edges.
  std::vector<std::vector<std::pair<int, bool>>> neighbours(unique.size());
  *closed = true;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i != 2) *closed = false;
    if (j - i == 2) {
      const bool same = uses[i].forward == uses[i + 1].forward;
      neighbours[uses[i].tri].push_back({uses[i + 1].tri, same});
      neighbours[uses[i + 1].tri].push_back({uses[i].tri, same});
    }
    i = j;
  }
  std::vector<int> flip(unique.size(), -1);
  std::vector<int> queue;
  std::vector<std::array<Vec3, 3>> out;
  out.reserve(unique.size());
  for (std::size_t seed = 0; seed < unique.size(); ++seed) {
    if (flip[seed] >= 0) continue;
    flip[seed] = 0;
    queue.assign(1, static_cast<int>(seed));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int t = queue[head];
      for (const auto& [other, same] : neighbours[t]) {
        if (flip[other] >= 0) {
          if (flip[other] != (same ? 1 - flip[t] : flip[t])) *closed = false;  // not orientable
          continue;
        }
        // Consistent: the shared edge traversed in opposite directions.
        flip[other] = same ? 1 - flip[t] : flip[t];
        queue.push_back(other);
      }
    }
    double volume = 0;
    const Vec3 ref = mesh_.vertices[mesh_.triangles[unique[seed].source][0]];
    for (int t : queue) {
      const auto& src = mesh_.triangles[unique[t].source];
      const Vec3 a = mesh_.vertices[src[0]] - ref, b = mesh_.vertices[src[1]] - ref, c = mesh_.vertices[src[2]] - ref;
      volume += (flip[t] ? -1.0 : 1.0) * a.dot(b.cross(c));
    }
    const bool invert = volume < 0;
    for (int t : queue) {
      const auto& src = mesh_.triangles[unique[t].source];
      const bool f = (flip[t] != 0) != invert;
      out.push_back({mesh_.vertices[src[0]], mesh_.vertices[src[f ? 2 : 1]], mesh_.vertices[src[f ? 1 : 2]]});
    }
  }
  return out;
}

void DistanceFieldBuilder::ComputeVotes() {
  bool closed = false;
  const std::vector<std::array<Vec3, 3>> oriented = OrientedTriangles(&closed);
  winding_ = closed;
  vote_.assign(n_, 0);
  std::vector<std::int32_t> bucket(n_);
  const std::int64_t dims[3] = {nx_, ny_, nz_};
  const std::int64_t stride[3] = {1, nx_, nx_ * ny_};
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    std::fill(bucket.begin(), bucket.end(), 0);
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads_)
    for (std::int64_t t = 0; t < static_cast<std::int64_t>(oriented.size()); ++t) {
      const auto& T = oriented[t];
      P2 p[3];
      for (int k = 0; k < 3; ++k) p[k] = {T[k][u], T[k][v]};
      const double area2 = (p[1].u - p[0].u) * (p[2].v - p[0].v) - (p[1].v - p[0].v) * (p[2].u - p[0].u);
      if (!(area2 != 0) || !std::isfinite(area2)) continue;
      const int sign = area2 > 0 ? 1 : -1;
      // Crossing coordinate along a: the plane through the triangle.
      const Vec3 n = (T[1] - T[0]).cross(T[2] - T[0]);
      if (n[a] == 0) continue;
      const P2 A = p[0], B = sign > 0 ? p[1] : p[2], C = sign > 0 ? p[2] : p[1];
      const double umin = std::min({A.u, B.u, C.u}), umax = std::max({A.u, B.u, C.u});
      const double vmin = std::min({A.v, B.v, C.v}), vmax = std::max({A.v, B.v, C.v});
      const std::int64_t iu0 =
          std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((umin - origin_[u]) / h_ - 0.5)));
      const std::int64_t iu1 =
          std::min<std::int64_t>(dims[u] - 1, static_cast<std::int64_t>(std::floor((umax - origin_[u]) / h_ - 0.5)));
      const std::int64_t iv0 =
          std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((vmin - origin_[v]) / h_ - 0.5)));
      const std::int64_t iv1 =
          std::min<std::int64_t>(dims[v] - 1, static_cast<std::int64_t>(std::floor((vmax - origin_[v]) / h_ - 0.5)));
      for (std::int64_t iv = iv0; iv <= iv1; ++iv) {
        const double pv = origin_[v] + (iv + 0.5) * h_;
        for (std::int64_t iu = iu0; iu <= iu1; ++iu) {
          const double pu = origin_[u] + (iu + 0.5) * h_;
          if (!InsideTopLeft(A, B, C, {pu, pv})) continue;
          const double c = T[0][a] - (n[u] * (pu - T[0][u]) + n[v] * (pv - T[0][v])) / n[a];
          const double f = std::floor((c - origin_[a]) / h_);
          const std::int64_t j = static_cast<std::int64_t>(std::clamp(f, 0.0, static_cast<double>(dims[a] - 1)));
          const std::int64_t index = j * stride[a] + iu * stride[u] + iv * stride[v];
          __atomic_fetch_add(&bucket[index], closed ? sign : 1, __ATOMIC_RELAXED);
        }
      }
    }
    // Per line: winding of the ray towards -a is -(sum of the buckets before
    // the cell), towards +a the sum after it (a crossing inside the cell
    // itself makes it a surface cell, whose vote is not used). Lines along y
    // and z are processed a row of x at a time, so that memory is read in
    // order.
    auto update = [&](std::int64_t index, std::int64_t total, std::int64_t before, std::int64_t here) {
      // Winding: -(crossings before) towards -a plus (crossings after)
      // towards +a; parity: the number of the two rays with an odd count.
      const std::int64_t after = total - before - here;
      const std::int64_t contribution = closed ? after - before : (after & 1) + (before & 1);
      const std::int64_t sum = vote_[index] + contribution;
      vote_[index] = static_cast<std::int16_t>(std::clamp<std::int64_t>(sum, -32000, 32000));
    };
    if (a == 0) {
#pragma omp parallel for schedule(static) num_threads(threads_)
      for (std::int64_t row = 0; row < ny_ * nz_; ++row) {
        const std::int64_t base = row * nx_;
        std::int64_t total = 0, before = 0;
        for (std::int64_t x = 0; x < nx_; ++x) total += bucket[base + x];
        for (std::int64_t x = 0; x < nx_; ++x) {
          update(base + x, total, before, bucket[base + x]);
          before += bucket[base + x];
        }
      }
    } else {
      // a = 1: per z, the rows y; a = 2: per y, the rows z.
      const std::int64_t outer = a == 1 ? nz_ : ny_, inner = a == 1 ? ny_ : nz_;
      const std::int64_t outer_stride = a == 1 ? nx_ * ny_ : nx_, inner_stride = a == 1 ? nx_ : nx_ * ny_;
#pragma omp parallel num_threads(threads_)
      {
        std::vector<std::int64_t> total(nx_), before(nx_);
#pragma omp for schedule(static)
        for (std::int64_t o = 0; o < outer; ++o) {
          std::fill(total.begin(), total.end(), 0);
          std::fill(before.begin(), before.end(), 0);
          for (std::int64_t j = 0; j < inner; ++j) {
            const std::int32_t* row = bucket.data() + o * outer_stride + j * inner_stride;
            for (std::int64_t x = 0; x < nx_; ++x) total[x] += row[x];
          }
          for (std::int64_t j = 0; j < inner; ++j) {
            const std::int64_t base = o * outer_stride + j * inner_stride;
            for (std::int64_t x = 0; x < nx_; ++x) {
              update(base + x, total[x], before[x], bucket[base + x]);
              before[x] += bucket[base + x];
            }
          }
        }
      }
    }
  }
}

void DistanceFieldBuilder::MarkBand() {
  // Separable 3x3x3 dilation of the surface cells, a row of x at a time.
  std::vector<std::uint8_t> a(n_), b(n_);
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::int64_t i = 0; i < n_; ++i) a[i] = slot_[i] >= 0;
    // x
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::int64_t row = 0; row < ny_ * nz_; ++row) {
    const std::uint8_t* src = a.data() + row * nx_;
    std::uint8_t* dst = b.data() + row * nx_;
    for (std::int64_t x = 0; x < nx_; ++x) {
      dst[x] = src[x] | (x > 0 ? src[x - 1] : 0) | (x + 1 < nx_ ? src[x + 1] : 0);
    }
  }
  // y (b -> a), then z (a -> b).
  for (int axis = 1; axis < 3; ++axis) {
    const std::vector<std::uint8_t>& src = axis == 1 ? b : a;
    std::vector<std::uint8_t>& dst = axis == 1 ? a : b;
    const std::int64_t outer = axis == 1 ? nz_ : ny_, inner = axis == 1 ? ny_ : nz_;
    const std::int64_t outer_stride = axis == 1 ? nx_ * ny_ : nx_, inner_stride = axis == 1 ? nx_ : nx_ * ny_;
#pragma omp parallel for schedule(static) num_threads(threads_)
    for (std::int64_t o = 0; o < outer; ++o) {
      for (std::int64_t j = 0; j < inner; ++j) {
        const std::int64_t base = o * outer_stride + j * inner_stride;
        const std::uint8_t* here = src.data() + base;
        const std::uint8_t* below = j > 0 ? here - inner_stride : here;
        const std::uint8_t* above = j + 1 < inner ? here + inner_stride : here;
        std::uint8_t* out = dst.data() + base;
        for (std::int64_t x = 0; x < nx_; ++x) out[x] = here[x] | below[x] | above[x];
      }
    }
  }
  band_.swap(b);
}

void DistanceFieldBuilder::ComputeBand() {
  field_->cells_.resize(n_);
  DistanceField::Cell* cells = field_->cells_.data();
  std::atomic<std::int64_t> slices_done{0};
#pragma omp parallel num_threads(threads_)
  {
    std::vector<std::uint32_t> stamp(tri_.size(), 0);
    std::uint32_t generation = 0;
    std::vector<std::int32_t> candidates;
    candidates.reserve(256);
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t z = 0; z < nz_; ++z) {
      for (std::int64_t y = 0; y < ny_; ++y) {
        for (std::int64_t x = 0; x < nx_; ++x) {
          const std::int64_t index = Index(x, y, z);
          DistanceField::Cell& cell = cells[index];
          if (!band_[index]) {
            cell.triangle = -1;
            continue;
          }
          if (++generation == 0) {
            std::fill(stamp.begin(), stamp.end(), 0);
            generation = 1;
          }
          candidates.clear();
          for (std::int64_t dz = std::max<std::int64_t>(0, z - 1); dz <= std::min(nz_ - 1, z + 1); ++dz) {
            for (std::int64_t dy = std::max<std::int64_t>(0, y - 1); dy <= std::min(ny_ - 1, y + 1); ++dy) {
              for (std::int64_t dx = std::max<std::int64_t>(0, x - 1); dx <= std::min(nx_ - 1, x + 1); ++dx) {
                const std::int32_t s = slot_[Index(dx, dy, dz)];
                if (s < 0) continue;
                for (std::int64_t k = list_begin_[s]; k < list_begin_[s + 1]; ++k) {
                  const std::int32_t t = list_tris_[k];
                  if (stamp[t] != generation) stamp[t] = generation, candidates.push_back(t);
                }
              }
            }
          }
          const Vec3 center = Center(x, y, z);
          double best = std::numeric_limits<double>::infinity();
          std::int32_t best_t = -1;
          Vec3 best_p = center;
          for (std::int32_t t : candidates) {
            const Vec3 q =
                ClosestPointOnTriangle(center, tri_[t][0], tri_[t][1], tri_[t][2], kDegenerate, kFaceWeights);
            const double d = (q - center).squaredNorm();
            if (d < best || (d == best && t < best_t)) best = d, best_t = t, best_p = q;
          }
          cell.nearest[0] = static_cast<float>(best_p.x());
          cell.nearest[1] = static_cast<float>(best_p.y());
          cell.nearest[2] = static_cast<float>(best_p.z());
          cell.triangle = best_t;
        }
      }
      const std::int64_t done = slices_done.fetch_add(1) + 1;
      if (omp_get_thread_num() == 0) Report(0.35 + 0.4 * static_cast<double>(done) / nz_);
    }
  }
}

void DistanceFieldBuilder::Propagate() {
  DistanceField::Cell* cells = field_->cells_.data();
  // Separable sweeps: along each axis, forward and backward, a cell takes its
  // predecessor's point when that is closer to its centre than its own. Two
  // rounds over x, y, z. Sweeps along y and z move whole rows at a time, so
  // that memory is read in order.
  auto relax = [](DistanceField::Cell& cell, const DistanceField::Cell& prev, double cx, double cy, double cz) {
    if (prev.triangle < 0) return;
    if (cell.triangle < 0) {
      cell = prev;
      return;
    }
    const double ox = cx - cell.nearest[0], oy = cy - cell.nearest[1], oz = cz - cell.nearest[2];
    const double px = cx - prev.nearest[0], py = cy - prev.nearest[1], pz = cz - prev.nearest[2];
    const double own = ox * ox + oy * oy + oz * oz, other = px * px + py * py + pz * pz;
    if (other < own || (other == own && prev.triangle < cell.triangle)) cell = prev;
  };
  for (int round = 0; round < 2; ++round) {
    // x: each row on its own.
#pragma omp parallel for schedule(static) num_threads(threads_)
    for (std::int64_t row = 0; row < ny_ * nz_; ++row) {
      const std::int64_t y = row % ny_, z = row / ny_;
      DistanceField::Cell* line = cells + row * nx_;
      const double cy = origin_.y() + (y + 0.5) * h_, cz = origin_.z() + (z + 0.5) * h_;
      for (std::int64_t x = 1; x < nx_; ++x) relax(line[x], line[x - 1], origin_.x() + (x + 0.5) * h_, cy, cz);
      for (std::int64_t x = nx_ - 2; x >= 0; --x) relax(line[x], line[x + 1], origin_.x() + (x + 0.5) * h_, cy, cz);
    }
    // y: per z slice, row after row.
#pragma omp parallel for schedule(static) num_threads(threads_)
    for (std::int64_t z = 0; z < nz_; ++z) {
      const double cz = origin_.z() + (z + 0.5) * h_;
      DistanceField::Cell* slice = cells + z * nx_ * ny_;
      for (int direction = 0; direction < 2; ++direction) {
        for (std::int64_t step = 1; step < ny_; ++step) {
          const std::int64_t y = direction == 0 ? step : ny_ - 1 - step;
          const std::int64_t prev = direction == 0 ? y - 1 : y + 1;
          const double cy = origin_.y() + (y + 0.5) * h_;
          for (std::int64_t x = 0; x < nx_; ++x) {
            relax(slice[y * nx_ + x], slice[prev * nx_ + x], origin_.x() + (x + 0.5) * h_, cy, cz);
          }
        }
      }
    }
    // z: per y, row after row.
#pragma omp parallel for schedule(static) num_threads(threads_)
    for (std::int64_t y = 0; y < ny_; ++y) {
      const double cy = origin_.y() + (y + 0.5) * h_;
      for (int direction = 0; direction < 2; ++direction) {
        for (std::int64_t step = 1; step < nz_; ++step) {
          const std::int64_t z = direction == 0 ? step : nz_ - 1 - step;
          const std::int64_t prev = direction == 0 ? z - 1 : z + 1;
          const double cz = origin_.z() + (z + 0.5) * h_;
          DistanceField::Cell* row = cells + (z * ny_ + y) * nx_;
          const DistanceField::Cell* prev_row = cells + (prev * ny_ + y) * nx_;
          for (std::int64_t x = 0; x < nx_; ++x) relax(row[x], prev_row[x], origin_.x() + (x + 0.5) * h_, cy, cz);
        }
      }
    }
  }
  const auto swept = std::chrono::steady_clock::now();
  // Refinement of the far cells: the closest point on the triangle received
  // and on those of the six face neighbours (read from a snapshot).
  std::vector<std::int32_t> snapshot(n_);
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::int64_t i = 0; i < n_; ++i) snapshot[i] = cells[i].triangle;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_)
  for (std::int64_t z = 0; z < nz_; ++z) {
    for (std::int64_t y = 0; y < ny_; ++y) {
      for (std::int64_t x = 0; x < nx_; ++x) {
        const std::int64_t index = Index(x, y, z);
        if (band_[index]) continue;
        DistanceField::Cell& cell = cells[index];
        std::int32_t tried[7];
        int n_tried = 0;
        const std::int32_t own = snapshot[index];
        std::int32_t neighbours[7] = {own, -1, -1, -1, -1, -1, -1};
        if (x > 0) neighbours[1] = snapshot[index - 1];
        if (x + 1 < nx_) neighbours[2] = snapshot[index + 1];
        if (y > 0) neighbours[3] = snapshot[index - nx_];
        if (y + 1 < ny_) neighbours[4] = snapshot[index + nx_];
        if (z > 0) neighbours[5] = snapshot[index - nx_ * ny_];
        if (z + 1 < nz_) neighbours[6] = snapshot[index + nx_ * ny_];
        const Vec3 center = Center(x, y, z);
        double best = std::numeric_limits<double>::infinity();
        std::int32_t best_t = -1;
        Vec3 best_p = center;
        for (std::int32_t t : neighbours) {
          if (t < 0 || std::find(tried, tried + n_tried, t) != tried + n_tried) continue;
          tried[n_tried++] = t;
          const Vec3 q = ClosestPointOnTriangle(center, tri_[t][0], tri_[t][1], tri_[t][2], kDegenerate, kFaceWeights);
          const double d = (q - center).squaredNorm();
          if (d < best || (d == best && t < best_t)) best = d, best_t = t, best_p = q;
        }
        if (best_t < 0) continue;
        cell.nearest[0] = static_cast<float>(best_p.x());
        cell.nearest[1] = static_cast<float>(best_p.y());
        cell.nearest[2] = static_cast<float>(best_p.z());
        cell.triangle = best_t;
      }
    }
  }
  LogDebug("distance field: refinement %.3f s",
           std::chrono::duration<double>(std::chrono::steady_clock::now() - swept).count());
}

void DistanceFieldBuilder::Classify() {
  field_->classes_.resize(n_);
  std::uint8_t* classes = field_->classes_.data();
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::int64_t i = 0; i < n_; ++i) {
    if (slot_[i] >= 0) {
      classes[i] = static_cast<std::uint8_t>(CellClass::kSurface);
    } else {
      // Winding: the mean of the six at least 1/2 in magnitude; parity: at
      // least five of the six rays odd (open meshes: a hole fools one ray).
      const int vote = std::abs(static_cast<int>(vote_[i]));
      classes[i] =
          static_cast<std::uint8_t>((winding_ ? vote >= 3 : vote >= 5) ? CellClass::kInside : CellClass::kOutside);
    }
  }
  std::vector<std::int32_t>().swap(slot_);
  std::vector<std::int16_t>().swap(vote_);
  std::vector<std::uint8_t>().swap(band_);
}

std::shared_ptr<DistanceField> BuildDistanceField(const TriangleMesh& mesh, const DistanceFieldOptions& options) {
  DistanceFieldBuilder builder(mesh, options);
  return builder.Build();
}

// ---------------------------------------------------------------------------
// Artifact and cache

namespace {

Provenance MakeFieldProvenance(const DistanceFieldProvenanceInfo& info) {
  Provenance provenance;
  provenance.producer = "ausbau-distfield";
  provenance.producer_version = AUSBAU_VERSION;
  provenance.parameters_yaml = "resolution: " + std::to_string(info.resolution) +
                               "\npadding: " + FormatDouble(info.padding) +
                               "\nalgorithm: " + std::to_string(kAlgorithmVersion) + "\n";
  provenance.inputs.emplace_back("mesh", info.mesh_hash);
  return provenance;
}

}  // namespace

std::string DistanceFieldProvenanceHash(const DistanceFieldProvenanceInfo& info) {
  return MakeFieldProvenance(info).Hash();
}

std::string DistanceFieldContentHash(const DistanceField& field) {
  Hasher hasher;
  const auto& d = field.dims();
  const std::int32_t dims[3] = {d[0], d[1], d[2]};
  const double geometry[4] = {field.origin().x(), field.origin().y(), field.origin().z(), field.spacing()};
  const std::int64_t triangles = field.triangle_count();
  hasher.Add(dims, sizeof dims).Add(geometry, sizeof geometry).Add(&triangles, sizeof triangles);
  hasher.Add(field.mesh_hash());
  const std::size_t n = static_cast<std::size_t>(field.size());
  hasher.Add(field.classes(), n);
  static_assert(sizeof(DistanceField::Cell) == 16, "a cell is 3 floats and an int32, no padding");
  hasher.Add(field.cells(), n * sizeof(DistanceField::Cell));
  return hasher.HexDigest();
}

void WriteDistanceField(const std::filesystem::path& path, const DistanceField& field, const std::string& units,
                        const std::string& frame) {
  const Provenance provenance = MakeFieldProvenance({field.mesh_hash(), field.resolution(), field.padding()});
  ArtifactWriter writer(path, kDistanceFieldSchema, kDistanceFieldSchemaVersion, provenance);
  const auto& d = field.dims();
  const std::size_t n = static_cast<std::size_t>(field.size());
  const std::vector<std::size_t> shape = {static_cast<std::size_t>(d[2]), static_cast<std::size_t>(d[1]),
                                          static_cast<std::size_t>(d[0])};
  {
    std::vector<std::uint8_t> classes(field.classes(), field.classes() + n);
    writer.WriteBytes("class", classes, shape);
  }
  {
    std::vector<std::int64_t> triangles(n);
    for (std::size_t i = 0; i < n; ++i) triangles[i] = field.cells()[i].triangle;
    writer.WriteInts("triangle", triangles, shape);
  }
  {
    std::vector<float> nearest(3 * n);
    for (std::size_t i = 0; i < n; ++i) std::memcpy(&nearest[3 * i], field.cells()[i].nearest, 3 * sizeof(float));
    writer.WriteFloats("nearest_point", nearest, {shape[0], shape[1], shape[2], 3});
  }
  writer.WriteDoubles("grid/origin", {field.origin().x(), field.origin().y(), field.origin().z()}, {3});
  writer.WriteDoubles("grid/spacing", {field.spacing()}, {});
  writer.WriteInts("grid/dims", {d[0], d[1], d[2]}, {3});
  const std::string unit_text = units.empty() ? "mesh units" : units;
  writer.SetAttribute("nearest_point", "units", unit_text);
  writer.SetAttribute("grid/origin", "units", unit_text);
  writer.SetAttribute("grid/spacing", "units", unit_text);
  writer.SetAttribute("", "units", unit_text);
  writer.SetAttribute("", "axis_order", std::string("z,y,x"));
  writer.SetAttribute("", "origin_x", field.origin().x());
  writer.SetAttribute("", "origin_y", field.origin().y());
  writer.SetAttribute("", "origin_z", field.origin().z());
  writer.SetAttribute("", "spacing", field.spacing());
  writer.SetAttribute("", "nx", static_cast<std::int64_t>(d[0]));
  writer.SetAttribute("", "ny", static_cast<std::int64_t>(d[1]));
  writer.SetAttribute("", "nz", static_cast<std::int64_t>(d[2]));
  writer.SetAttribute("", "resolution", static_cast<std::int64_t>(field.resolution()));
  writer.SetAttribute("", "padding", field.padding());
  writer.SetAttribute("", "mesh_hash", field.mesh_hash());
  writer.SetAttribute("", "triangles", field.triangle_count());
  writer.SetAttribute("", "frame", frame.empty() ? std::string("mesh coordinates") : frame);
  writer.SetAttribute("", "class_values", std::string("0 outside, 1 inside, 2 surface"));
  writer.SetAttribute("", "content_hash", DistanceFieldContentHash(field));
  writer.Commit();
}

std::shared_ptr<DistanceField> ReadDistanceField(const std::filesystem::path& path) {
  ArtifactReader reader(path, kDistanceFieldSchema, kDistanceFieldSchemaVersion);
  const std::string where = path.string();
  auto field = std::make_shared<DistanceField>();
  const Array<double> origin = reader.ReadDoubles("grid/origin", 1);
  const Array<double> spacing = reader.ReadDoubles("grid/spacing", 0);
  const Array<std::int64_t> dims = reader.ReadInts("grid/dims", 1);
  if (origin.data.size() != 3 || dims.data.size() != 3 || spacing.data.size() != 1) {
    throw InputErrorAt(where, "grid/origin and grid/dims must hold 3 values, grid/spacing one");
  }
  if (!(spacing.data[0] > 0) || !std::isfinite(spacing.data[0]))
    throw InputErrorAt(where, "grid/spacing must be positive");
  for (int k = 0; k < 3; ++k) {
    if (dims.data[k] < 1 || dims.data[k] > 4 * kMaxDistanceFieldResolution) {
      throw InputErrorAt(where, "grid/dims out of range");
    }
    field->dims_[k] = static_cast<int>(dims.data[k]);
    field->origin_[k] = origin.data[k];
  }
  if (!field->origin_.allFinite() || !std::isfinite(spacing.data[0] * 4 * kMaxDistanceFieldResolution) ||
      !(field->origin_ + field->spacing_ * Eigen::Vector3d::Constant(4.0 * kMaxDistanceFieldResolution)).allFinite()) {
    throw InputErrorAt(where, "grid/origin or grid/spacing is not finite or out of range");
  }
  field->spacing_ = spacing.data[0];
  field->resolution_ = static_cast<int>(reader.ReadIntAttribute("", "resolution"));
  field->padding_ = reader.ReadDoubleAttribute("", "padding");
  field->mesh_hash_ = reader.ReadStringAttribute("", "mesh_hash");
  field->triangle_count_ = reader.ReadIntAttribute("", "triangles");
  // Cells store int32 triangle indices; a mesh has at least one triangle.
  if (field->triangle_count_ < 1 || field->triangle_count_ > std::numeric_limits<std::int32_t>::max()) {
    throw InputErrorAt(where,
                       "root attribute 'triangles' is out of range (" + std::to_string(field->triangle_count_) + ")");
  }
  const std::size_t n = static_cast<std::size_t>(field->size());
  const std::vector<std::size_t> shape = {static_cast<std::size_t>(field->dims_[2]),
                                          static_cast<std::size_t>(field->dims_[1]),
                                          static_cast<std::size_t>(field->dims_[0])};
  auto check_shape = [&](const std::string& name, const std::vector<std::size_t>& got,
                         const std::vector<std::size_t>& expected) {
    if (got != expected) throw InputErrorAt(where, "dataset '" + name + "' does not match grid/dims");
  };
  {
    Array<std::uint8_t> classes = reader.ReadBytes("class", 3);
    check_shape("class", classes.dims, shape);
    for (std::uint8_t c : classes.data) {
      if (c > 2) throw InputErrorAt(where, "dataset 'class' holds a value other than 0, 1, 2");
    }
    field->classes_ = std::move(classes.data);
  }
  field->cells_.resize(n);
  {
    const Array<std::int64_t> triangles = reader.ReadInts("triangle", 3);
    check_shape("triangle", triangles.dims, shape);
    for (std::size_t i = 0; i < n; ++i) {
      const std::int64_t t = triangles.data[i];
      if (t < 0 || t >= field->triangle_count_)
        throw InputErrorAt(where, "dataset 'triangle' holds an index out of range");
      field->cells_[i].triangle = static_cast<std::int32_t>(t);
    }
  }
  {
    const Array<float> nearest = reader.ReadFloats("nearest_point", 4);
    check_shape("nearest_point", nearest.dims, {shape[0], shape[1], shape[2], 3});
    for (std::size_t i = 0; i < n; ++i) {
      // A NaN point would make every distance and cell look-up from it undefined.
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(nearest.data[3 * i + k])) {
          throw InputErrorAt(where, "dataset 'nearest_point' holds a non-finite value at cell " + std::to_string(i));
        }
      }
      std::memcpy(field->cells_[i].nearest, &nearest.data[3 * i], 3 * sizeof(float));
    }
  }
  // The provenance says what the field was built from, not that these are
  // the cells that were built: an edited or damaged cell would pass every
  // check above and give wrong distances. The content hash written with
  // the cells tells.
  if (reader.ReadStringAttribute("", "content_hash") != DistanceFieldContentHash(*field)) {
    throw InputErrorAt(where, "the field does not match its content_hash (edited or damaged)");
  }
  return field;
}

namespace {

// Whether `path` holds a field with the provenance `expected` whose cells
// are the ones written (content_hash); a field that is not says so in one
// line, so that the caller builds it again.
bool VerifiedField(const std::filesystem::path& path, const std::string& expected, const std::string& name) {
  if (ExistingProvenanceHash(path, kDistanceFieldSchema, kDistanceFieldSchemaVersion) != expected) return false;
  try {
    ReadDistanceField(path);
    return true;
  } catch (const InputError& e) {
    LogWarn("%s: %s; building it again", name.c_str(), e.what());
    return false;
  }
}

}  // namespace

std::filesystem::path DistanceFieldCachePath(const std::filesystem::path& cache_dir, const std::string& mesh_hash,
                                             int resolution) {
  return cache_dir / ("distfield-" + mesh_hash.substr(0, 16) + "-r" + std::to_string(resolution) + ".h5");
}

std::filesystem::path DefaultDistanceFieldCacheDir(const std::filesystem::path& scene_file) {
  const char* env = std::getenv("AUSBAU_CACHE_DIR");
  if (env != nullptr && env[0] != '\0') return std::filesystem::path(env);
  std::filesystem::path dir = scene_file.parent_path();
  if (dir.empty()) dir = ".";
  // A scene folder marked read-only (no owner write bit, e.g. shared
  // benchmark data) is left alone, even for root: the user's cache instead.
  std::error_code error;
  const auto permissions = std::filesystem::status(dir, error).permissions();
  if (!error && (permissions & std::filesystem::perms::owner_write) == std::filesystem::perms::none) {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    if (xdg != nullptr && xdg[0] != '\0') return std::filesystem::path(xdg) / "ausbau";
    if (home != nullptr && home[0] != '\0') return std::filesystem::path(home) / ".cache" / "ausbau";
    // No user cache to go to: no cache at all. A fixed folder in the
    // system's temporary directory (as before) is shared by every user of
    // the machine, who could plant fields there for the next run to trust.
    LogInfo(
        "no cache for the distance fields: %s is read-only and neither XDG_CACHE_HOME nor HOME is set "
        "(set AUSBAU_CACHE_DIR to keep them)",
        dir.string().c_str());
    return std::filesystem::path();
  }
  return dir / ".ausbau-cache";
}

std::shared_ptr<DistanceField> LoadOrBuildDistanceField(const TriangleMesh& mesh, const DistanceFieldOptions& options,
                                                        const std::filesystem::path& cache_dir, const std::string& name,
                                                        const std::string& units, const std::string& frame,
                                                        CachedFieldInfo* info) {
  options.Check();
  const auto begin = std::chrono::steady_clock::now();
  auto seconds = [&begin] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count(); };
  CachedFieldInfo local;
  CachedFieldInfo& out = info != nullptr ? *info : local;
  out = CachedFieldInfo{};
  const std::string mesh_hash = MeshContentHash(mesh);
  if (!cache_dir.empty()) {
    const std::filesystem::path path = DistanceFieldCachePath(cache_dir, mesh_hash, options.resolution);
    const std::string expected = DistanceFieldProvenanceHash({mesh_hash, options.resolution, options.padding});
    if (ExistingProvenanceHash(path, kDistanceFieldSchema, kDistanceFieldSchemaVersion) == expected) {
      try {
        auto field = ReadDistanceField(path);
        if (field->mesh_hash() == mesh_hash &&
            field->triangle_count() == static_cast<std::int64_t>(mesh.triangles.size())) {
          out.path = path;
          out.reused = true;
          out.seconds = seconds();
          LogInfo("%s: reused %s (%.2f s)", name.c_str(), path.string().c_str(), out.seconds);
          return field;
        }
      } catch (const InputError& e) {
        LogWarn("%s: cached field unreadable, rebuilding: %s", name.c_str(), e.what());
      }
    }
    auto field = BuildDistanceField(mesh, options);
    const double build_s = seconds();
    try {
      std::filesystem::create_directories(cache_dir);
      WriteDistanceField(path, *field, units, frame);
      out.path = path;
    } catch (const std::exception& e) {
      LogWarn("%s: cannot write the cache file %s (%s); continuing without it", name.c_str(), path.string().c_str(),
              e.what());
    }
    out.seconds = build_s;
    LogInfo("%s: built %d x %d x %d cells in %.2f s%s%s", name.c_str(), field->dims()[0], field->dims()[1],
            field->dims()[2], build_s, out.path.empty() ? "" : ", cached in ", out.path.string().c_str());
    return field;
  }
  auto field = BuildDistanceField(mesh, options);
  out.seconds = seconds();
  return field;
}

std::filesystem::path MakeDistanceFieldFile(const TriangleMesh& mesh, const DistanceFieldOptions& options,
                                            const std::filesystem::path& cache_dir,
                                            const std::filesystem::path& explicit_target, bool force,
                                            const std::string& name, const std::string& units,
                                            const std::string& frame) {
  namespace fs = std::filesystem;
  const std::string mesh_hash = MeshContentHash(mesh);
  const std::string expected = DistanceFieldProvenanceHash({mesh_hash, options.resolution, options.padding});
  if (cache_dir.empty() && explicit_target.empty()) {
    throw InputError(
        "--output-dir: there is no cache to build the fields into (DefaultDistanceFieldCacheDir); "
        "give --output-dir or set AUSBAU_CACHE_DIR");
  }
  // No cache: the target alone.
  const fs::path cached =
      cache_dir.empty() ? fs::path() : DistanceFieldCachePath(cache_dir, mesh_hash, options.resolution);
  const fs::path target = explicit_target.empty() ? cached : explicit_target;
  PlanDistanceField(mesh, options);  // the memory guard, before any work
  if (!force && VerifiedField(target, expected, name)) {
    LogInfo("%s: %s is up to date (same mesh and resolution); use --force to build again", name.c_str(),
            target.string().c_str());
    return target;
  }
  if (!force && !cached.empty() && target != cached && VerifiedField(cached, expected, name)) {
    // Copy the cached file (atomically: a temporary beside the target, then rename).
    if (!target.parent_path().empty()) fs::create_directories(target.parent_path());
    const fs::path temporary = target.string() + ".tmp-" + std::to_string(::getpid());
    fs::copy_file(cached, temporary, fs::copy_options::overwrite_existing);
    fs::rename(temporary, target);
    LogInfo("%s: copied from the cache %s", name.c_str(), cached.string().c_str());
    return target;
  }
  const auto field = BuildDistanceField(mesh, options);
  WriteDistanceField(target, *field, units, frame);
  LogInfo("%s: %d x %d x %d cells (cell %g %s), written to %s", name.c_str(), field->dims()[0], field->dims()[1],
          field->dims()[2], field->spacing(), units.empty() ? "units" : units.c_str(), target.string().c_str());
  if (!cached.empty() && target != cached) {
    try {
      fs::create_directories(cache_dir);
      WriteDistanceField(cached, *field, units, frame);
    } catch (const std::exception& e) {
      LogWarn("%s: cannot write the cache file %s (%s)", name.c_str(), cached.string().c_str(), e.what());
    }
  }
  return target;
}

}  // namespace ausbau
