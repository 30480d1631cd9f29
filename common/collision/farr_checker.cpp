#include "collision/farr_checker.h"

#include <fcl/math/geometry.h>
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "core/error.h"
#include "core/log.h"
#include "geometry/weld.h"

namespace ausbau {

using Vec3 = Eigen::Vector3d;

void FarrOptions::Check() const {
  if (rays < 0 || rays > kMaxRays) {
    throw InputError("FARR rays must lie in [0, " + std::to_string(kMaxRays) + "] (got " + std::to_string(rays) + ")");
  }
  if (max_alternations < 1 || max_alternations > 1000) throw InputError("FARR alternations must lie in [1, 1000]");
  if (!(epsilon >= 0) || !std::isfinite(epsilon)) throw InputError("FARR epsilon must be >= 0");
  if (!(band >= 0) || !std::isfinite(band)) throw InputError("FARR band must be >= 0");
  if (!(stall >= 0 && stall < 1)) throw InputError("FARR stall must lie in [0, 1)");
}

// ---------------------------------------------------------------------------
// Robust triangle-triangle test (Moeller's interval test, accepting only
// proper crossings).

bool RobustTrianglesIntersect(const Vec3 p_in[3], const Vec3 q_in[3], double tolerance) {
  // Work relative to q[0] so that rounding scales with the triangles, not
  // with their distance from the origin.
  const Vec3 o = q_in[0];
  const Vec3 p[3] = {p_in[0] - o, p_in[1] - o, p_in[2] - o};
  const Vec3 q[3] = {Vec3::Zero(), q_in[1] - o, q_in[2] - o};
  double extent = 0;
  for (int i = 0; i < 3; ++i) extent = std::max({extent, p[i].norm(), q[i].norm()});
  if (!(extent > 0) || !std::isfinite(extent)) return false;

  // Signed distances (scaled by |n|) of one triangle's vertices to the
  // other's plane; every one must be clearly non-zero.
  auto plane_side = [&](const Vec3 t[3], const Vec3 s[3], double d[3]) -> bool {
    const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
    const Vec3 n = e1.cross(e2);
    const double scale = e1.norm() * e2.norm();
    if (!(n.norm() > tolerance * scale) || !(scale > 0)) return false;  // sliver or degenerate
    const double tol = tolerance * scale * extent;
    for (int i = 0; i < 3; ++i) {
      d[i] = n.dot(s[i] - t[0]);
      if (!(std::abs(d[i]) > tol)) return false;
    }
    return true;
  };
  double dp[3], dq[3];  // p's vertices against q's plane, q's against p's
  if (!plane_side(q, p, dp)) return false;
  if ((dp[0] > 0) == (dp[1] > 0) && (dp[1] > 0) == (dp[2] > 0)) return false;
  if (!plane_side(p, q, dq)) return false;
  if ((dq[0] > 0) == (dq[1] > 0) && (dq[1] > 0) == (dq[2] > 0)) return false;

  const Vec3 np = (p[1] - p[0]).cross(p[2] - p[0]), nq = (q[1] - q[0]).cross(q[2] - q[0]);
  const Vec3 line = np.cross(nq);
  if (!(line.norm() > 1e-6 * np.norm() * nq.norm())) return false;  // nearly parallel planes
  const Vec3 dir = line.normalized();

  // The interval a triangle cuts out of the line: the lone vertex (on its own
  // side of the other plane) against the other two.
  auto interval = [&dir](const Vec3 t[3], const double d[3], double* lo, double* hi) {
    int lone = 0;
    if ((d[0] > 0) == (d[1] > 0))
      lone = 2;
    else if ((d[0] > 0) == (d[2] > 0))
      lone = 1;
    const int i1 = (lone + 1) % 3, i2 = (lone + 2) % 3;
    const double pl = dir.dot(t[lone]), p1 = dir.dot(t[i1]), p2 = dir.dot(t[i2]);
    const double s1 = pl + (p1 - pl) * d[lone] / (d[lone] - d[i1]);
    const double s2 = pl + (p2 - pl) * d[lone] / (d[lone] - d[i2]);
    *lo = std::min(s1, s2);
    *hi = std::max(s1, s2);
  };
  double plo, phi, qlo, qhi;
  interval(p, dp, &plo, &phi);
  interval(q, dq, &qlo, &qhi);
  const double overlap = std::min(phi, qhi) - std::max(plo, qlo);
  return overlap > tolerance * extent * 1e3;
}

// ---------------------------------------------------------------------------
// The checker

struct FarrCollisionChecker::FieldView {
  float origin[3];
  float inv_h;
  float max_index[3];
  std::int64_t stride_y, stride_z;
  const DistanceField::Cell* cells;
  const std::uint8_t* classes;
  float gate2;  // squared distance below which a look-up triggers a pair test

  explicit FieldView(const DistanceField& f, double gate) {
    for (int k = 0; k < 3; ++k) {
      origin[k] = static_cast<float>(f.origin()[k]);
      max_index[k] = static_cast<float>(f.dims()[k] - 1);
    }
    inv_h = static_cast<float>(1.0 / f.spacing());
    stride_y = f.dims()[0];
    stride_z = static_cast<std::int64_t>(f.dims()[0]) * f.dims()[1];
    cells = f.cells();
    classes = f.classes();
    gate2 = static_cast<float>(gate * gate);
  }
  // The cell of (x, y, z), or of its projection onto the grid.
  std::int64_t Locate(float x, float y, float z) const {
    const float fx = std::min(std::max((x - origin[0]) * inv_h, 0.0f), max_index[0]);
    const float fy = std::min(std::max((y - origin[1]) * inv_h, 0.0f), max_index[1]);
    const float fz = std::min(std::max((z - origin[2]) * inv_h, 0.0f), max_index[2]);
    return static_cast<std::int64_t>(fx) + stride_y * static_cast<std::int64_t>(fy) +
           stride_z * static_cast<std::int64_t>(fz);
  }
};

namespace {

std::uint64_t SplitMix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// The per-query stream: seeded from the checker's seed and the pose's bits.
class PoseStream {
 public:
  PoseStream(std::uint64_t seed, const Pose& pose) {
    std::uint64_t h = SplitMix(seed ^ 0x4641525246415252ULL);
    const double values[7] = {pose.t.x(), pose.t.y(), pose.t.z(), pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()};
    for (double v : values) {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h = SplitMix(h ^ bits);
    }
    state_ = h;
  }
  // Uniform in [0, n).
  std::uint32_t Index(std::uint32_t n) {
    state_ += 0x9e3779b97f4a7c15ULL;
    const std::uint64_t r = SplitMix(state_);
    return static_cast<std::uint32_t>((static_cast<unsigned __int128>(r) * n) >> 64);
  }

 private:
  std::uint64_t state_;
};

// Recently tested patch pairs of a query, so that converging rays do not
// repeat the same tests.
struct PairCache {
  static constexpr int kSize = 32;
  std::uint64_t keys[kSize];
  int count = 0, next = 0;
  bool Insert(std::uint64_t key) {  // false when already present
    for (int i = 0; i < count; ++i) {
      if (keys[i] == key) return false;
    }
    keys[next] = key;
    next = (next + 1) % kSize;
    count = std::min(count + 1, kSize);
    return true;
  }
};

}  // namespace

// Per mesh: its vertices and triangles, each triangle's plane, and its
// patch: the triangle and its edge neighbours (vertices compared by
// position; geometric twins such as the back faces of double-sided exports
// left out).
struct FarrCollisionChecker::MeshData {
  static constexpr int kPatch = 6;
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<std::int32_t, kPatch>> patches;  // -1 padded; [0] = the triangle itself
  std::vector<Vec3> normals;                              // (v1 - v0) x (v2 - v0)

  explicit MeshData(const TriangleMesh& mesh) : vertices(mesh.vertices), triangles(mesh.triangles) {
    const std::size_t n = triangles.size();
    normals.resize(n);
    for (std::size_t t = 0; t < n; ++t) {
      const auto& tri = triangles[t];
      normals[t] = (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]);
    }
    const std::vector<int> merged = WeldExactPositions(vertices);
    struct Use {
      std::uint64_t edge;
      std::int32_t tri;
    };
    std::vector<Use> uses;
    uses.reserve(3 * n);
    std::vector<std::array<int, 3>> sorted(n);
    for (std::size_t t = 0; t < n; ++t) {
      std::array<int, 3> v = {merged[triangles[t][0]], merged[triangles[t][1]], merged[triangles[t][2]]};
      for (int k = 0; k < 3; ++k) {
        const int a = v[k], b = v[(k + 1) % 3];
        if (a == b) continue;
        uses.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b)),
                        static_cast<std::int32_t>(t)});
      }
      std::sort(v.begin(), v.end());
      sorted[t] = v;
    }
    std::sort(uses.begin(), uses.end(),
              [](const Use& x, const Use& y) { return x.edge < y.edge || (x.edge == y.edge && x.tri < y.tri); });
    patches.assign(n, {});
    std::vector<int> fill(n, 1);
    for (std::size_t t = 0; t < n; ++t) {
      patches[t].fill(-1);
      patches[t][0] = static_cast<std::int32_t>(t);
    }
    for (std::size_t i = 0; i < uses.size();) {
      std::size_t j = i;
      while (j < uses.size() && uses[j].edge == uses[i].edge) ++j;
      for (std::size_t x = i; x < j; ++x) {
        const int t = uses[x].tri;
        for (std::size_t y = i; y < j; ++y) {
          const int u = uses[y].tri;
          if (u == t || sorted[u] == sorted[t] || fill[t] >= kPatch) continue;
          bool twin = false;  // a geometric copy of one already in the patch
          for (int q = 0; q < fill[t]; ++q) twin = twin || sorted[patches[t][q]] == sorted[u];
          if (!twin) patches[t][fill[t]++] = u;
        }
      }
      i = j;
    }
  }
};

// Per-query transform data; FCL's relative transform is computed on the
// first full pair test only.
struct FarrCollisionChecker::QueryFrame {
  Eigen::Matrix3d R;
  Vec3 t;
  bool fcl_ready = false;
  Eigen::Matrix3d fcl_R;
  Vec3 fcl_T;
};

// The online cost model of the adaptive mode (see farr_checker.h).
struct FarrCollisionChecker::Adaptive {
  std::vector<int> candidates;  // ascending, the last = options.rays
  std::atomic<int> rays{0};     // current choice
  // Explored queries (a uniform sample of all), those that ran rays, and per
  // lowest witness ray r: how many, and FCL's time on them (what r + 1 or
  // more rays save).
  std::atomic<std::int64_t> explored{0}, explored_probed{0};
  std::atomic<std::int64_t> witness_count[FarrOptions::kMaxRays] = {};
  std::atomic<std::int64_t> witness_fcl_ns[FarrOptions::kMaxRays] = {};
  // Work of the explored probes without a witness (look-ups per ray), their
  // time (cold caches), and the time of every 8th regular probe without a
  // witness (warm).
  std::atomic<std::int64_t> explore_lookups{0}, explore_rays{0}, explore_ns{0};
  std::atomic<std::int64_t> warm_lookups{0}, warm_ns{0};
  std::atomic<std::int64_t> fcl_ns{0};  // FCL's time on all explored queries
  std::mutex update;
};

FarrCollisionChecker::FarrCollisionChecker(const TriangleMesh& robot, const TriangleMesh& environment,
                                           std::shared_ptr<const DistanceField> robot_field,
                                           std::shared_ptr<const DistanceField> environment_field, std::uint64_t seed,
                                           const FarrOptions& options)
    : fcl_(robot, environment),
      robot_field_(std::move(robot_field)),
      environment_field_(std::move(environment_field)),
      seed_(seed),
      options_(options) {
  options_.Check();
  if (!robot_field_ || !environment_field_) throw std::invalid_argument("FARR: both distance fields are required");
  if (robot_field_->mesh_hash() != MeshContentHash(robot)) {
    throw std::invalid_argument("FARR: D's distance field was built for another mesh");
  }
  if (environment_field_->mesh_hash() != MeshContentHash(environment)) {
    throw std::invalid_argument("FARR: S's distance field was built for another mesh");
  }
  robot_ = std::make_unique<MeshData>(robot);
  environment_ = std::make_unique<MeshData>(environment);
  adaptive_ = std::make_unique<Adaptive>();
  // On or off: all `rays` rays, or none. (Intermediate k would fit the
  // cost model too, but its estimates are too noisy to pick them well.)
  adaptive_->candidates = {0, options_.rays};
  adaptive_->rays.store(options_.rays);
  const double sqrt3 = std::sqrt(3.0);
  const double diagonal = robot.Bounds().Diagonal();
  const double eps = options_.epsilon * diagonal;
  epsilon2_ = eps * eps;
  robot_view_ =
      std::make_unique<FieldView>(*robot_field_, std::max(eps, options_.band * sqrt3 * robot_field_->spacing()));
  environment_view_ = std::make_unique<FieldView>(*environment_field_,
                                                  std::max(eps, options_.band * sqrt3 * environment_field_->spacing()));
  std::vector<int> incident(robot.vertices.size(), -1);
  for (std::size_t t = 0; t < robot.triangles.size(); ++t) {
    for (int v : robot.triangles[t]) {
      if (incident[v] < 0) incident[v] = static_cast<int>(t);
    }
  }
  std::vector<char> used(environment.vertices.size(), 0);
  for (const auto& t : environment.triangles) {
    for (int v : t) used[v] = 1;
  }
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (used[v]) environment_vertices_.push_back(static_cast<int>(v));
  }
  for (std::size_t v = 0; v < incident.size(); ++v) {
    if (incident[v] < 0) continue;
    start_vertices_.push_back(static_cast<int>(v));
    start_triangle_.push_back(incident[v]);
    robot_radius_ = std::max(robot_radius_, robot.vertices[v].norm());
  }
}

FarrCollisionChecker::~FarrCollisionChecker() = default;

// The triangles of D's patch around robot_triangle against those of S's
// patch around environment_triangle. A pair is tested only when each
// triangle straddles the other's plane; then by the robust test in world
// coordinates, confirmed by FCL's leaf test in FCL's frame (D's mesh frame, S
// moved by the relative transform), exactly as FCL's traversal calls it.
bool FarrCollisionChecker::PatchWitness(QueryFrame& frame, int robot_triangle, int environment_triangle, bool* rejected,
                                        std::int64_t* pair_tests) const {
  constexpr int kPatch = MeshData::kPatch;
  const auto& dp = robot_->patches[robot_triangle];
  const auto& sp = environment_->patches[environment_triangle];
  Vec3 p[kPatch][3], np[kPatch];
  double offset[kPatch];
  int m = 0;
  for (; m < kPatch && dp[m] >= 0; ++m) {
    const auto& tri = robot_->triangles[dp[m]];
    for (int k = 0; k < 3; ++k) p[m][k] = frame.R * robot_->vertices[tri[k]] + frame.t;
    np[m] = frame.R * robot_->normals[dp[m]];
    offset[m] = np[m].dot(p[m][0]);
  }
  for (int j = 0; j < kPatch && sp[j] >= 0; ++j) {
    const auto& stri = environment_->triangles[sp[j]];
    const Vec3 q[3] = {environment_->vertices[stri[0]], environment_->vertices[stri[1]],
                       environment_->vertices[stri[2]]};
    const Vec3& nq = environment_->normals[sp[j]];
    const double qoff = nq.dot(q[0]);
    for (int i = 0; i < m; ++i) {
      // Cheap rejection: one triangle entirely on one side of the other's plane.
      const double a0 = np[i].dot(q[0]) - offset[i], a1 = np[i].dot(q[1]) - offset[i], a2 = np[i].dot(q[2]) - offset[i];
      if ((a0 > 0 && a1 > 0 && a2 > 0) || (a0 < 0 && a1 < 0 && a2 < 0)) continue;
      const double b0 = nq.dot(p[i][0]) - qoff, b1 = nq.dot(p[i][1]) - qoff, b2 = nq.dot(p[i][2]) - qoff;
      if ((b0 > 0 && b1 > 0 && b2 > 0) || (b0 < 0 && b1 < 0 && b2 < 0)) continue;
      ++*pair_tests;
      if (!RobustTrianglesIntersect(p[i], q)) continue;
      if (!frame.fcl_ready) {
        const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
        const Vec3 zero = Vec3::Zero();
        fcl::relativeTransform(frame.R, frame.t, identity, zero, frame.fcl_R, frame.fcl_T);
        frame.fcl_ready = true;
      }
      const auto& rtri = robot_->triangles[dp[i]];
      if (fcl::detail::Intersect<double>::intersect_Triangle(robot_->vertices[rtri[0]], robot_->vertices[rtri[1]],
                                                             robot_->vertices[rtri[2]], q[0], q[1], q[2], frame.fcl_R,
                                                             frame.fcl_T)) {
        return true;
      }
      *rejected = true;
    }
  }
  return false;
}

bool FarrCollisionChecker::Skip(const Pose& pose) const {
  if (!pose.t.allFinite()) return true;
  // D's bounding sphere (about its reference point) clear of S by the
  // field's estimate: no ray can end on a crossing. Only a shortcut to FCL.
  const FieldView& s = *environment_view_;
  const float x = static_cast<float>(pose.t.x()), y = static_cast<float>(pose.t.y()),
              z = static_cast<float>(pose.t.z());
  const DistanceField::Cell& c = s.cells[s.Locate(x, y, z)];
  const double dx = x - c.nearest[0], dy = y - c.nearest[1], dz = z - c.nearest[2];
  const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
  return d > 1.1 * robot_radius_ + 2.0 * environment_field_->spacing();
}

// Kept as one function (about 150 lines) on purpose: FARR's inner loop
// (thesis 4.2.3), run for every collision query before FCL; the rays'
// stack arrays (kMaxRays) and the march through both distance fields share
// its locals, and a split would pass them by reference per ray step.
FarrCollisionChecker::ProbeResult FarrCollisionChecker::Rays(const Pose& pose, int rays, bool complete) const {
  constexpr int kMax = FarrOptions::kMaxRays;
  ProbeResult result;
  const int k = std::min(rays, kMax);
  if (k <= 0 || start_vertices_.empty()) return result;
  if (!pose.t.allFinite() || !pose.q.coeffs().allFinite()) return result;  // no look-ups: FCL decides
  QueryFrame frame;
  frame.R = pose.q.toRotationMatrix();
  frame.t = pose.t;
  float R[9], t[3];
  for (int i = 0; i < 3; ++i) {
    t[i] = static_cast<float>(pose.t[i]);
    for (int j = 0; j < 3; ++j) R[3 * i + j] = static_cast<float>(frame.R(i, j));
  }
  const FieldView& sv = *environment_view_;
  const FieldView& dv = *robot_view_;
  const float eps2 = static_cast<float>(epsilon2_);
  const float gate_s = std::max(sv.gate2, eps2), gate_d = std::max(dv.gate2, eps2);
  const bool stall = options_.stall > 0;
  const float stall_factor = static_cast<float>((1.0 - options_.stall) * (1.0 - options_.stall));

  // Ray state, structure of arrays; the active rays are kept in the first
  // n_active lanes, so that the arithmetic loops vectorize.
  alignas(64) float ax[kMax], ay[kMax], az[kMax];  // a on D (D's frame)
  alignas(64) float wx[kMax], wy[kMax], wz[kMax];  // a in the world
  alignas(64) float bx[kMax], by[kMax], bz[kMax];  // b on S (world, then D's frame)
  alignas(64) float cx[kMax], cy[kMax], cz[kMax];  // a' on D
  alignas(64) float d2[kMax], last_d2[kMax];
  alignas(64) std::int32_t ta[kMax], tb[kMax], tc[kMax];
  alignas(64) std::int64_t index[kMax];
  std::int32_t id[kMax];  // the ray's number (lanes are compacted)
  PoseStream stream(seed_, pose);
  const std::uint32_t n_start = static_cast<std::uint32_t>(start_vertices_.size());
  for (int r = 0; r < k; ++r) {
    const std::uint32_t pick = stream.Index(n_start);
    const Vec3& v = robot_->vertices[start_vertices_[pick]];
    ax[r] = static_cast<float>(v.x());
    ay[r] = static_cast<float>(v.y());
    az[r] = static_cast<float>(v.z());
    ta[r] = start_triangle_[pick];
    last_d2[r] = std::numeric_limits<float>::infinity();
    id[r] = r;
  }
  result.rays_used = k;
  int n = k;
  PairCache tested;
  bool rejected = false;
  std::int64_t pair_tests = 0;
  auto test = [&](std::int32_t robot_t, std::int32_t env_t) {
    const std::uint64_t key =
        (static_cast<std::uint64_t>(static_cast<std::uint32_t>(robot_t)) << 32) | static_cast<std::uint32_t>(env_t);
    if (!tested.Insert(key)) return false;
    return PatchWitness(frame, robot_t, env_t, &rejected, &pair_tests);
  };
  int best = kMax;  // complete: the lowest ray number with a witness so far
  auto finish = [&](int lane) {
    if (lane >= 0) best = std::min(best, id[lane]);
    result.witness = best < kMax;
    result.witness_ray = best < kMax ? best : -1;
    pair_tests_.fetch_add(pair_tests, std::memory_order_relaxed);
    if (rejected) pair_rejects_.fetch_add(1, std::memory_order_relaxed);
    return result;
  };
  // Cell index of lane r's point (x, y, z) in `view` (vectorizable).
  auto locate = [](const FieldView& view, const float* x, const float* y, const float* z, int count,
                   std::int64_t* out) {
#pragma omp simd
    for (int r = 0; r < count; ++r) {
      const float fx = std::min(std::max((x[r] - view.origin[0]) * view.inv_h, 0.0f), view.max_index[0]);
      const float fy = std::min(std::max((y[r] - view.origin[1]) * view.inv_h, 0.0f), view.max_index[1]);
      const float fz = std::min(std::max((z[r] - view.origin[2]) * view.inv_h, 0.0f), view.max_index[2]);
      out[r] = static_cast<std::int64_t>(static_cast<std::int32_t>(fx)) +
               view.stride_y * static_cast<std::int32_t>(fy) + view.stride_z * static_cast<std::int32_t>(fz);
    }
  };

  for (int iteration = 0; iteration < options_.max_alternations && n > 0; ++iteration) {
    result.lookups += 2 * n;
    // a (on D) -> world.
#pragma omp simd
    for (int r = 0; r < n; ++r) {
      wx[r] = R[0] * ax[r] + R[1] * ay[r] + R[2] * az[r] + t[0];
      wy[r] = R[3] * ax[r] + R[4] * ay[r] + R[5] * az[r] + t[1];
      wz[r] = R[6] * ax[r] + R[7] * ay[r] + R[8] * az[r] + t[2];
    }
    // -> S's field: b, the nearest point on S (independent loads).
    locate(sv, wx, wy, wz, n, index);
    for (int r = 0; r < n; ++r) {
      const DistanceField::Cell& cell = sv.cells[index[r]];
      bx[r] = cell.nearest[0];
      by[r] = cell.nearest[1];
      bz[r] = cell.nearest[2];
      tb[r] = cell.triangle;
    }
#pragma omp simd
    for (int r = 0; r < n; ++r) {
      const float dx = wx[r] - bx[r], dy = wy[r] - by[r], dz = wz[r] - bz[r];
      d2[r] = dx * dx + dy * dy + dz * dz;
    }
    for (int r = 0; r < n; ++r) {
      if (id[r] < best && d2[r] <= gate_s && test(ta[r], tb[r])) {
        if (!complete) return finish(r);
        best = std::min(best, id[r]);
      }
    }
    // b in D's frame: R^T (b - t).
#pragma omp simd
    for (int r = 0; r < n; ++r) {
      const float ux = bx[r] - t[0], uy = by[r] - t[1], uz = bz[r] - t[2];
      bx[r] = R[0] * ux + R[3] * uy + R[6] * uz;
      by[r] = R[1] * ux + R[4] * uy + R[7] * uz;
      bz[r] = R[2] * ux + R[5] * uy + R[8] * uz;
    }
    // -> D's field: a', the nearest point on D.
    locate(dv, bx, by, bz, n, index);
    for (int r = 0; r < n; ++r) {
      const DistanceField::Cell& cell = dv.cells[index[r]];
      cx[r] = cell.nearest[0];
      cy[r] = cell.nearest[1];
      cz[r] = cell.nearest[2];
      tc[r] = cell.triangle;
    }
#pragma omp simd
    for (int r = 0; r < n; ++r) {
      const float dx = bx[r] - cx[r], dy = by[r] - cy[r], dz = bz[r] - cz[r];
      d2[r] = dx * dx + dy * dy + dz * dz;
    }
    for (int r = 0; r < n; ++r) {
      if (id[r] < best && d2[r] <= gate_d && test(tc[r], tb[r])) {
        if (!complete) return finish(r);
        best = std::min(best, id[r]);
      }
    }
    // a <- a'; a ray ends when a' == a (a local distance minimum, alg. 6
    // line 12) or, with `stall`, when it no longer gets closer.
    int kept = 0;
    for (int r = 0; r < n; ++r) {
      if (id[r] >= best) continue;  // complete: cannot lower the witness ray any more
      if (cx[r] == ax[r] && cy[r] == ay[r] && cz[r] == az[r]) continue;
      if (stall && d2[r] >= stall_factor * last_d2[r]) continue;
      ax[kept] = cx[r];
      ay[kept] = cy[r];
      az[kept] = cz[r];
      ta[kept] = tc[r];
      id[kept] = id[r];
      last_d2[kept] = d2[r];
      ++kept;
    }
    n = kept;
  }
  return finish(-1);
}

bool FarrCollisionChecker::Contained(const Pose& pose) const {
  // One side inside the other: of k random vertices (at least 16) none in an
  // outside cell of the other's field and at least one in an inside cell.
  // (Surface cells are undecided; an open mesh may fool single points, not
  // all of them.)
  const int k = std::max(16, options_.rays);
  const Eigen::Matrix3d R = pose.q.toRotationMatrix();
  auto test = [k](const DistanceField& field, const std::vector<int>& vertices, PoseStream& stream, auto&& map) {
    if (vertices.empty()) return false;
    bool inside = false;
    for (int i = 0; i < k; ++i) {
      const int v = vertices[stream.Index(static_cast<std::uint32_t>(vertices.size()))];
      const CellClass c = field.cell_class(field.Locate(map(v)));
      if (c == CellClass::kOutside) return false;
      inside = inside || c == CellClass::kInside;
    }
    return inside;
  };
  PoseStream stream(seed_ ^ 0x636f6e7461696eULL, pose);
  if (test(*environment_field_, start_vertices_, stream,
           [&](int v) { return Vec3(R * robot_->vertices[v] + pose.t); })) {
    return true;
  }
  return test(*robot_field_, environment_vertices_, stream,
              [&](int v) { return Vec3(R.transpose() * (environment_->vertices[v] - pose.t)); });
}

FarrCollisionChecker::ProbeResult FarrCollisionChecker::Probe(const Pose& pose, int rays, bool complete) const {
  return Rays(pose, rays, complete);
}

bool FarrCollisionChecker::InCollision(const Pose& pose) const {
  using Clock = std::chrono::steady_clock;
  const std::int64_t query = queries_.fetch_add(1, std::memory_order_relaxed);
  const bool containment = options_.report_containment || options_.count_containment;
  const bool adaptive = options_.adaptive && options_.rays > 0 && !containment;
  // Exploration: the first 64 queries, then every 32nd, after 4096 queries
  // every 256th, after 65536 every 1024th.
  const std::int64_t explore_mask = query < 4096 ? 31 : query < 65536 ? 255 : 1023;
  const bool explore = adaptive && (query < 64 || (query & explore_mask) == 0);
  const int rays = adaptive && !explore ? adaptive_->rays.load(std::memory_order_relaxed) : options_.rays;
  Adaptive& model = *adaptive_;
  auto nanoseconds = [](Clock::time_point from) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - from).count();
  };
  bool answer = false;
  bool answered = false;
  ProbeResult probe;
  if (rays <= 0 && !containment) {
    // Plain FCL.
  } else if (!containment && Skip(pose)) {
    skipped_.fetch_add(1, std::memory_order_relaxed);
  } else {
    const bool timed = explore || (adaptive && (query & 7) == 3);
    const Clock::time_point begin = timed ? Clock::now() : Clock::time_point();
    probe = Probe(pose, rays, explore);
    if (timed) {
      const std::int64_t ns = nanoseconds(begin);
      if (explore) {
        model.explored_probed.fetch_add(1, std::memory_order_relaxed);
        if (!probe.witness) {
          model.explore_lookups.fetch_add(probe.lookups, std::memory_order_relaxed);
          model.explore_rays.fetch_add(probe.rays_used, std::memory_order_relaxed);
          model.explore_ns.fetch_add(ns, std::memory_order_relaxed);
        }
      } else if (!probe.witness) {
        model.warm_lookups.fetch_add(probe.lookups, std::memory_order_relaxed);
        model.warm_ns.fetch_add(ns, std::memory_order_relaxed);
      }
    }
    if (probe.witness) {
      witnesses_.fetch_add(1, std::memory_order_relaxed);
      answer = answered = true;
    }
  }
  if (!answered || explore) {
    // FCL: the answer, or (exploring, after a witness) only its time.
    const Clock::time_point begin = explore ? Clock::now() : Clock::time_point();
    const bool fcl = fcl_.InCollision(pose);
    if (explore) {
      const std::int64_t ns = nanoseconds(begin);
      model.fcl_ns.fetch_add(ns, std::memory_order_relaxed);
      if (probe.witness) {
        model.witness_fcl_ns[probe.witness_ray].fetch_add(ns, std::memory_order_relaxed);
        model.witness_count[probe.witness_ray].fetch_add(1, std::memory_order_relaxed);
      }
    }
    if (!answered) {
      fcl_calls_.fetch_add(1, std::memory_order_relaxed);
      if (fcl) fcl_collisions_.fetch_add(1, std::memory_order_relaxed);
      answer = fcl;
      if (!fcl && containment && Contained(pose)) {
        containments_.fetch_add(1, std::memory_order_relaxed);
        if (options_.report_containment) answer = true;
      }
    }
  }
  if (explore) model.explored.fetch_add(1, std::memory_order_relaxed);
  if (adaptive && (query & (query < 4096 ? 63 : 255)) == 63) Recompute();
  return answer;
}

void FarrCollisionChecker::Recompute() const {
  // Expected time per query with k rays, from the explored sample:
  //   cost(k)   = k * cost_per_ray * (probed queries not proven by k rays) / explored
  //   saving(k) = (FCL's time on the explored queries proven by k rays) / explored
  // (FCL's time on exactly those: deep collisions, which rays find, are the
  // ones FCL decides fast too). k minimizes cost - saving; k = 0 costs and
  // saves nothing.
  Adaptive& model = *adaptive_;
  std::unique_lock<std::mutex> lock(model.update, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const double explored = static_cast<double>(model.explored.load());
  const double explore_rays = static_cast<double>(model.explore_rays.load());
  const double explore_lookups = static_cast<double>(model.explore_lookups.load());
  if (explored < 64 || explore_rays < 1 || explore_lookups < 1) return;  // not enough evidence yet
  const double warm_lookups = static_cast<double>(model.warm_lookups.load());
  const double ns_per_lookup = warm_lookups >= 2000 ? static_cast<double>(model.warm_ns.load()) / warm_lookups
                                                    : static_cast<double>(model.explore_ns.load()) / explore_lookups;
  const double cost_per_ray = explore_lookups / explore_rays * ns_per_lookup;
  const double probed = static_cast<double>(model.explored_probed.load());
  const int current = model.rays.load();
  double best_value = 0, current_value = 0;
  int best_k = 0;
  double saved_ns = 0, proven = 0;
  int next_ray = 0;
  for (int k : model.candidates) {
    for (; next_ray < k; ++next_ray) {
      saved_ns += static_cast<double>(model.witness_fcl_ns[next_ray].load());
      proven += static_cast<double>(model.witness_count[next_ray].load());
    }
    const double value = (k * cost_per_ray * std::max(0.0, probed - proven) - saved_ns) / explored;
    if (value < best_value) best_value = value, best_k = k;
    if (k == current) current_value = value;
  }
  // Hysteresis: change only for a gain of 2% of FCL's mean time per query.
  const double threshold = 0.02 * static_cast<double>(model.fcl_ns.load()) / explored;
  if (best_value > current_value - threshold) best_k = current;
  if (best_k != current) {
    LogDebug(
        "FARR: %d rays from now on (%.1f look-ups of %.1f ns per ray, %s; %.0f of %.0f explored queries "
        "proven, saving %.0f ns per query)",
        best_k, explore_lookups / explore_rays, ns_per_lookup, warm_lookups >= 2000 ? "warm" : "cold", proven, explored,
        saved_ns / explored);
  }
  model.rays.store(best_k);
}

FarrStats FarrCollisionChecker::stats() const {
  FarrStats s;
  s.queries = queries_.load();
  s.witnesses = witnesses_.load();
  s.fcl_calls = fcl_calls_.load();
  s.fcl_collisions = fcl_collisions_.load();
  s.containments = containments_.load();
  s.skipped = skipped_.load();
  s.pair_tests = pair_tests_.load();
  s.pair_rejects = pair_rejects_.load();
  s.explored = adaptive_->explored.load();
  s.rays_now = options_.adaptive ? adaptive_->rays.load() : options_.rays;
  return s;
}

void FarrCollisionChecker::ResetStats() const {
  for (auto* counter : {&queries_, &witnesses_, &fcl_calls_, &fcl_collisions_, &containments_, &skipped_, &pair_tests_,
                        &pair_rejects_}) {
    counter->store(0);
  }
}

}  // namespace ausbau
