#include "inistate/voxel_grid.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <unordered_map>

#include "core/cancel.h"
#include "core/error.h"
#include "core/log.h"
#include "geometry/closest_point.h"
#include "geometry/principal_axes.h"
#include "geometry/triangle_box.h"
#include "geometry/weld.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

// ---------------------------------------------------------------- geometry

// ---------------------------------------------------------------- topology

struct Topology {
  std::vector<int> closed, open;  // triangle indices
  std::vector<bool> flip;         // per triangle of the mesh
};

int Find(std::vector<int>& parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// Splits the triangles into closed and open edge-connected components
// (vertices welded by position) and orients them (see voxel_grid.h).
Topology AnalyzeTopology(const TriangleMesh& mesh) {
  const int nt = static_cast<int>(mesh.triangles.size());
  // Welded indices count in order of first appearance, so they order the
  // vertices as their first input indices do (the edge balance below).
  const std::vector<int> weld = WeldExactPositions(mesh.vertices);
  std::vector<int> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<bool> valid(nt, false);
  struct EdgeInfo {
    int balance = 0;  // +1 per use low->high, -1 per use high->low
    int triangle = -1;
  };
  std::unordered_map<std::uint64_t, EdgeInfo> edges;
  edges.reserve(3 * static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    const int w[3] = {weld[tri[0]], weld[tri[1]], weld[tri[2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;  // degenerate: no area, no edges
    valid[t] = true;
    for (int k = 0; k < 3; ++k) {
      const int u = w[k], v = w[(k + 1) % 3];
      const std::uint64_t key =
          (static_cast<std::uint64_t>(std::min(u, v)) << 32) | static_cast<std::uint32_t>(std::max(u, v));
      EdgeInfo& e = edges[key];
      e.balance += u < v ? 1 : -1;
      if (e.triangle < 0) {
        e.triangle = t;
      } else {
        const int a = Find(parent, e.triangle), b = Find(parent, t);
        if (a != b) parent[a] = b;
      }
    }
  }
  std::vector<bool> open(nt, false);  // per component root
  for (const auto& [key, e] : edges) {
    if (e.balance != 0) open[Find(parent, e.triangle)] = true;
  }
  // Orientation: signed volume about the component's centroid.
  std::vector<Vec3> centroid(nt, Vec3::Zero());
  std::vector<double> weight(nt, 0.0), volume(nt, 0.0);
  for (int t = 0; t < nt; ++t) {
    if (!valid[t]) continue;
    const int r = Find(parent, t);
    for (int v : mesh.triangles[t]) centroid[r] += mesh.vertices[v];
    weight[r] += 3;
  }
  for (int t = 0; t < nt; ++t) {
    if (!valid[t]) continue;
    const int r = Find(parent, t);
    const Vec3 c = centroid[r] / weight[r];
    const auto& tri = mesh.triangles[t];
    volume[r] += (mesh.vertices[tri[0]] - c).dot((mesh.vertices[tri[1]] - c).cross(mesh.vertices[tri[2]] - c));
  }
  Topology out;
  out.flip.assign(nt, false);
  for (int t = 0; t < nt; ++t) {
    if (!valid[t]) continue;
    const int r = Find(parent, t);
    out.flip[t] = volume[r] < 0;
    (open[r] ? out.open : out.closed).push_back(t);
  }
  return out;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Reports progress (VoxelizeOptions::progress) from the master thread of a
// parallel loop.
class ParallelProgress {
 public:
  ParallelProgress(const ProgressCallback& report, std::int64_t total) : report_(report), total_(total) {}
  void Add(std::int64_t n) {
    if (!report_) return;
    const std::int64_t done = done_.fetch_add(n, std::memory_order_relaxed) + n;
    if (omp_get_thread_num() == 0) report_(done, total_);
  }
  // After the loop: the last report, and Cancelled when the loop's body
  // skipped its work because the run was cancelled (core/cancel.h).
  void Finish() {
    if (report_) report_(total_, total_);
    ThrowIfCancelled();
  }

 private:
  const ProgressCallback& report_;
  std::int64_t total_;
  std::atomic<std::int64_t> done_{0};
};

}  // namespace

// ---------------------------------------------------------------- grids

Vec3 VoxelGridGeometry::Center(std::int64_t index) const {
  const Eigen::Vector3i c = Cell(index);
  return Center(c.x(), c.y(), c.z());
}

Aabb VoxelGridGeometry::Bounds() const {
  Aabb box;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 along((corner & 1) ? dims[0] : 0, (corner & 2) ? dims[1] : 0, (corner & 4) ? dims[2] : 0);
    box.Extend(origin + axes * (spacing * along));
  }
  return box;
}

std::int64_t VoxelGrid::Count(VoxelState state) const {
  return std::count(cells.begin(), cells.end(), static_cast<std::uint8_t>(state));
}

// ---------------------------------------------------------------- BVH

// ---------------------------------------------------------------- voxelization

void VoxelizeOptions::Check() const {
  if (!(voxel_size >= 0) || !std::isfinite(voxel_size)) {
    throw OptionError(&voxel_size, "voxel_size", "must be >= 0 (0 = automatic), got " + std::to_string(voxel_size));
  }
  if (voxel_budget < 1)
    throw OptionError(&voxel_budget, "voxel_budget", "must be >= 1, got " + std::to_string(voxel_budget));
  if (memory_limit < 1) throw OptionError(&memory_limit, "memory_limit", "must be > 0");
  if (!(shrink >= 0) || !std::isfinite(shrink))
    throw OptionError(&shrink, "shrink", "must be >= 0, got " + std::to_string(shrink));
  if (!(winding_threshold > 0 && winding_threshold < 1))
    throw OptionError(&winding_threshold, "winding_threshold", "must lie in (0, 1)");
}

double AutomaticVoxelSize(const Aabb& box, std::int64_t budget) {
  if (box.Empty()) throw InputError("cannot size voxels for an empty mesh");
  const double diagonal = box.Diagonal();
  const Vec3 extent = box.Size().cwiseMax(Vec3::Constant(0.01 * diagonal));
  const double size = std::cbrt(extent.prod() / static_cast<double>(std::max<std::int64_t>(budget, 1)));
  if (!(size > 0) || !std::isfinite(size)) throw InputError("cannot size voxels for a mesh of zero extent");
  return size;
}

VoxelGridGeometry GridAround(const Aabb& box, double spacing, int padding) {
  if (box.Empty()) throw InputError("cannot build a voxel grid around an empty mesh");
  VoxelGridGeometry g;
  g.spacing = spacing;
  const Vec3 size = box.Size();
  for (int k = 0; k < 3; ++k) {
    // floor + 1 cells cover the box with a margin in (0, spacing] to share
    // out, so that no face lies on the padding voxels' boundary.
    const double n = std::floor(size[k] / spacing) + 1.0 + 2.0 * padding;
    if (!(n <= 1e9)) {
      throw InputError("voxel grid of " + std::to_string(n) + " voxels along an axis (voxel size " +
                       std::to_string(spacing) + "): choose a larger --voxel-size");
    }
    g.dims[k] = std::max(1, static_cast<int>(n));
  }
  g.origin = box.Center() - 0.5 * spacing * Vec3(g.dims[0], g.dims[1], g.dims[2]);
  return g;
}

std::int64_t VoxelizeMemoryBytes(const VoxelGridGeometry& g) {
  // A state byte and a 4-byte region label per voxel while voxelizing, and a
  // distance byte per voxel in IntersectionVolume.
  const double bytes = 6.0 * g.dims[0] * static_cast<double>(g.dims[1]) * g.dims[2];
  return bytes > 9e18 ? std::numeric_limits<std::int64_t>::max() : static_cast<std::int64_t>(bytes);
}

// The triangle/voxel tests VoxelizeMesh's surface pass makes: the voxels of
// each triangle's box in the grid's frame, clipped to the grid.
double SurfaceTests(const TriangleMesh& mesh, const VoxelGridGeometry& g) {
  const Eigen::Matrix3d to_grid = g.axes.transpose();
  const Vec3 origin = to_grid * g.origin;
  double total = 0;
  for (const auto& tri : mesh.triangles) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int corner = 0; corner < 3; ++corner) {
      const Vec3 p = (to_grid * mesh.vertices[tri[corner]] - origin) / g.spacing;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    double voxels = 1;
    for (int k = 0; k < 3; ++k) {
      const double first = std::max(0.0, std::floor(lo[k])), last = std::min(g.dims[k] - 1.0, std::floor(hi[k]));
      voxels *= std::max(0.0, last - first + 1);
    }
    total += voxels;
  }
  return total;
}

void CheckVoxelMemory(const VoxelGridGeometry& g, std::int64_t limit, const std::string& what) {
  const std::int64_t bytes = VoxelizeMemoryBytes(g);
  if (bytes > limit) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: %d x %d x %d voxels of size %g need %.2f GiB, over the limit of %.2f GiB "
                  "(choose a larger --voxel-size or raise --memory-limit)",
                  what.c_str(), g.dims[0], g.dims[1], g.dims[2], g.spacing, bytes / double(1 << 30),
                  limit / double(1 << 30));
    throw InputError(buf);
  }
}

// Kept as one function (about 140 lines) on purpose: its parallel passes
// (surface voxels, then the inside fill by winding numbers) share the grid,
// the topology and the progress reporter; the five steps are numbered below.
VoxelGrid VoxelizeMesh(const TriangleMesh& mesh, const VoxelGridGeometry& geometry, const VoxelizeOptions& options,
                       VoxelizeStats* stats_out) {
  if (!geometry.axes.isIdentity(0)) {
    // A turned grid: voxelize the mesh in the grid's frame, where the grid
    // is axis-aligned (the winding number does not depend on the frame).
    TriangleMesh local = mesh;
    for (Vec3& v : local.vertices) v = geometry.axes.transpose() * v;
    VoxelGridGeometry aligned = geometry;
    aligned.origin = geometry.axes.transpose() * geometry.origin;
    aligned.axes = Eigen::Matrix3d::Identity();
    VoxelGrid grid = VoxelizeMesh(local, aligned, options, stats_out);
    grid.geometry = geometry;
    return grid;
  }
  const auto start = std::chrono::steady_clock::now();
  VoxelizeStats stats;
  VoxelGrid grid;
  grid.geometry = geometry;
  const std::int64_t count = geometry.Count();
  grid.cells.assign(static_cast<size_t>(count), kVoxelEmpty);
  const double h = geometry.spacing;
  const int nx = geometry.dims[0], ny = geometry.dims[1], nz = geometry.dims[2];
  std::uint8_t* cells = grid.cells.data();

  // 1. Surface voxels: every voxel whose box a triangle touches.
  {
    // Cubic voxels, so the test rounds as for a cube (as recorded).
    const double half = 0.5 * h * (1 + 1e-9);
    const Vec3 half_extent = Vec3::Constant(half);
    const std::int64_t nt = static_cast<std::int64_t>(mesh.triangles.size());
    ParallelProgress progress(options.progress, nt);
#pragma omp parallel for schedule(dynamic, 64)
    for (std::int64_t t = 0; t < nt; ++t) {
      if (CancelRequested()) continue;  // ParallelProgress::Finish throws
      const auto& tri = mesh.triangles[t];
      const Vec3& a = mesh.vertices[tri[0]];
      const Vec3& b = mesh.vertices[tri[1]];
      const Vec3& c = mesh.vertices[tri[2]];
      const Vec3 lo = (a.cwiseMin(b).cwiseMin(c) - geometry.origin) / h;
      const Vec3 hi = (a.cwiseMax(b).cwiseMax(c) - geometry.origin) / h;
      const int i0 = std::max(0, static_cast<int>(std::floor(lo.x() - 1e-6)));
      const int j0 = std::max(0, static_cast<int>(std::floor(lo.y() - 1e-6)));
      const int k0 = std::max(0, static_cast<int>(std::floor(lo.z() - 1e-6)));
      const int i1 = std::min(nx - 1, static_cast<int>(std::floor(hi.x() + 1e-6)));
      const int j1 = std::min(ny - 1, static_cast<int>(std::floor(hi.y() + 1e-6)));
      const int k1 = std::min(nz - 1, static_cast<int>(std::floor(hi.z() + 1e-6)));
      for (int k = k0; k <= k1; ++k) {
        for (int j = j0; j <= j1; ++j) {
          for (int i = i0; i <= i1; ++i) {
            const std::int64_t index = geometry.Index(i, j, k);
            if (__atomic_load_n(&cells[index], __ATOMIC_RELAXED) == kVoxelSurface) continue;
            const Vec3 center = geometry.Center(i, j, k);
            if (TriangleOverlapsBox(center, half_extent, a, b, c, SatRounding::kCubeHalfSize)) {
              __atomic_store_n(&cells[index], static_cast<std::uint8_t>(kVoxelSurface), __ATOMIC_RELAXED);
            }
          }
        }
      }
      progress.Add(1);
    }
    progress.Finish();
  }

  // 2. Closed and open components of the mesh.
  const Topology topology = AnalyzeTopology(mesh);
  stats.closed_triangles = static_cast<std::int64_t>(topology.closed.size());
  stats.open_triangles = static_cast<std::int64_t>(topology.open.size());
  const WindingBvh closed(mesh, &topology.closed, &topology.flip);
  const WindingBvh open(mesh, &topology.open, &topology.flip);

  // 3. 6-connected regions of non-surface voxels.
  std::vector<std::int32_t> region(static_cast<size_t>(count), -1);
  std::vector<std::int64_t> representative;
  {
    std::vector<std::int64_t> queue;
    const std::int64_t plane = std::int64_t{nx} * ny;
    for (std::int64_t seed = 0; seed < count; ++seed) {
      if (cells[seed] != kVoxelEmpty || region[seed] >= 0) continue;
      const std::int32_t r = static_cast<std::int32_t>(representative.size());
      representative.push_back(seed);
      region[seed] = r;
      queue.assign(1, seed);
      for (size_t head = 0; head < queue.size(); ++head) {
        const std::int64_t v = queue[head];
        const int i = static_cast<int>(v % nx), j = static_cast<int>((v / nx) % ny), k = static_cast<int>(v / plane);
        auto visit = [&](std::int64_t n) {
          if (cells[n] == kVoxelEmpty && region[n] < 0) {
            region[n] = r;
            queue.push_back(n);
          }
        };
        if (i > 0) visit(v - 1);
        if (i + 1 < nx) visit(v + 1);
        if (j > 0) visit(v - nx);
        if (j + 1 < ny) visit(v + nx);
        if (k > 0) visit(v - plane);
        if (k + 1 < nz) visit(v + plane);
      }
    }
  }
  stats.regions = static_cast<std::int64_t>(representative.size());

  // 4. The closed part's winding number, once per region (an integer).
  std::vector<double> region_winding(representative.size(), 0.0);
  if (!closed.empty()) {
    const std::int64_t nr = static_cast<std::int64_t>(representative.size());
#pragma omp parallel for schedule(dynamic, 16)
    for (std::int64_t r = 0; r < nr; ++r) {
      region_winding[r] = std::round(closed.WindingNumber(geometry.Center(representative[r])));
    }
    stats.winding_evaluations += nr;
  }

  // 5. Inside voxels: closed part per region plus the open part per voxel.
  {
    const double threshold = options.winding_threshold;
    std::atomic<std::int64_t> evaluations{0};
    const std::int64_t slab = std::int64_t{nx} * ny;
    const ProgressCallback silent;
    ParallelProgress progress(open.empty() ? silent : options.progress, nz);
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < nz; ++k) {
      if (CancelRequested()) continue;  // ParallelProgress::Finish throws
      std::int64_t local = 0;
      for (std::int64_t v = k * slab; v < (k + 1) * slab; ++v) {
        if (cells[v] != kVoxelEmpty) continue;
        double w = region_winding[region[v]];
        if (!open.empty()) {
          w += open.WindingNumber(geometry.Center(v));
          ++local;
        }
        if (w >= threshold) cells[v] = kVoxelInside;
      }
      evaluations.fetch_add(local, std::memory_order_relaxed);
      progress.Add(1);
    }
    progress.Finish();
    stats.winding_evaluations += evaluations.load();
  }

  stats.surface = grid.Count(kVoxelSurface);
  stats.inside = grid.Count(kVoxelInside);
  stats.time_s = Seconds(start);
  if (stats_out != nullptr) *stats_out = stats;
  return grid;
}

VoxelGrid ErodeVoxels(const VoxelGrid& grid, double distance) {
  if (!(distance > 0)) return grid;
  const VoxelGridGeometry& g = grid.geometry;
  const double r = distance / g.spacing;
  const int reach = static_cast<int>(std::floor(r));
  std::vector<std::array<int, 3>> ball;
  for (int dk = -reach; dk <= reach; ++dk) {
    for (int dj = -reach; dj <= reach; ++dj) {
      for (int di = -reach; di <= reach; ++di) {
        if ((di || dj || dk) && di * di + dj * dj + dk * dk <= r * r + 1e-9) ball.push_back({di, dj, dk});
      }
    }
  }
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  std::vector<std::uint8_t> kept(grid.cells.size(), 0);
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        if (grid.cells[g.Index(i, j, k)] == kVoxelEmpty) continue;
        bool keep = true;
        for (const auto& o : ball) {
          if (!grid.Occupied(i + o[0], j + o[1], k + o[2])) {
            keep = false;
            break;
          }
        }
        kept[g.Index(i, j, k)] = keep ? 1 : 0;
      }
    }
  }
  VoxelGrid out;
  out.geometry = g;
  out.cells.assign(grid.cells.size(), kVoxelEmpty);
  auto is_kept = [&](int i, int j, int k) { return g.Contains(i, j, k) && kept[g.Index(i, j, k)] != 0; };
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        if (!kept[g.Index(i, j, k)]) continue;
        const bool interior = is_kept(i - 1, j, k) && is_kept(i + 1, j, k) && is_kept(i, j - 1, k) &&
                              is_kept(i, j + 1, k) && is_kept(i, j, k - 1) && is_kept(i, j, k + 1);
        out.cells[g.Index(i, j, k)] = interior ? kVoxelInside : kVoxelSurface;
      }
    }
  }
  return out;
}

SceneVoxels VoxelizeScene(const Scene& scene, const VoxelizeOptions& options) {
  options.Check();
  const auto check_size = [&](const TriangleMesh& mesh, const std::string& file, const char* what) {
    if (static_cast<std::int64_t>(mesh.triangles.size()) > options.max_triangles) {
      throw InputErrorAt(file, std::string(what) + " has " + std::to_string(mesh.triangles.size()) +
                                   " triangles, more than the voxelizer takes (" +
                                   std::to_string(options.max_triangles) + "; decimate the mesh)");
    }
  };
  check_size(scene.static_mesh, scene.static_files.empty() ? scene.file.string() : scene.static_files[0].string(), "S");
  check_size(scene.dynamic_mesh, scene.dynamic_file.string(), "D");
  // D in its principal frame (voxel_grid.h).
  const std::vector<Vec3>& d_points = scene.dynamic_mesh.vertices;
  const Eigen::Matrix3d d_axes = PrincipalAxes(d_points);
  Aabb d_box;
  for (const Vec3& p : d_points) d_box.Extend(d_axes.transpose() * p);
  // S in the frame of D's principal axes at the installed pose (S is mostly
  // what D is fitted into, turned with it), where D can reach in the volume
  // phase: within D's diagonal of D's installed box in that frame (scene
  // convention: world = start (p - dynamic_origin)).
  const Eigen::Matrix3d s_axes = scene.start.q.normalized().toRotationMatrix() * d_axes;
  Aabb s_box;
  for (const Vec3& p : scene.static_mesh.vertices) s_box.Extend(s_axes.transpose() * p);
  if (!options.whole_static && !d_box.Empty() && !s_box.Empty()) {
    Aabb installed;
    for (const Vec3& p : d_points) installed.Extend(s_axes.transpose() * scene.start.Apply(p - scene.dynamic_origin));
    const Vec3 reach = Vec3::Constant(installed.Diagonal());
    Aabb near;
    near.min = s_box.min.cwiseMax(installed.min - reach);
    near.max = s_box.max.cwiseMin(installed.max + reach);
    if ((near.min.array() <= near.max.array()).all()) {
      if (near.min != s_box.min || near.max != s_box.max) {
        LogInfo("S voxelized within D's diagonal (%g) of D's installed box: %g x %g x %g of S's %g x %g x %g",
                installed.Diagonal(), near.Size().x(), near.Size().y(), near.Size().z(), s_box.Size().x(),
                s_box.Size().y(), s_box.Size().z());
      }
      s_box = near;
    }
  }
  // A grid with the given axes around a box in the axes' frame.
  const auto grid_in = [](const Aabb& local, const Eigen::Matrix3d& axes, double spacing) {
    VoxelGridGeometry g = GridAround(local, spacing);
    g.origin = axes * g.origin;
    g.axes = axes;
    return g;
  };
  double h = options.voxel_size > 0 ? options.voxel_size : AutomaticVoxelSize(d_box, options.voxel_budget);
  VoxelGridGeometry gd = grid_in(d_box, d_axes, h), gs = grid_in(s_box, s_axes, h);
  if (options.voxel_size <= 0) {
    // The automatic size is a wish, not a demand: where S is much larger than
    // D its grid may not fit the memory limit at the budget's size; then
    // coarsen (by 2^(1/3), halving the cell count) until both grids fit, and
    // say so. An explicit --voxel-size is never changed (refused below).
    const double wished = h;
    // At most 2^30 times fewer cells; a limit below even that is refused below.
    const auto too_much = [&] {
      return VoxelizeMemoryBytes(gd) + VoxelizeMemoryBytes(gs) > options.memory_limit ||
             gd.Count() + gs.Count() > options.max_voxels ||
             SurfaceTests(scene.dynamic_mesh, gd) + SurfaceTests(scene.static_mesh, gs) > options.max_surface_tests;
    };
    for (int k = 0; k < 90 && too_much(); ++k) {
      h *= std::cbrt(2.0);
      gd = grid_in(d_box, d_axes, h);
      gs = grid_in(s_box, s_axes, h);
    }
    if (h != wished) {
      LogWarn(
          "automatic voxel size %g coarsened to %g to fit the memory limit of %.2f GiB (--memory-limit) and the "
          "work bounds (%lld voxels, %.0f triangle/voxel tests)",
          wished, h, options.memory_limit / double(1 << 30), static_cast<long long>(options.max_voxels),
          options.max_surface_tests);
    }
  }
  CheckVoxelMemory(gd, options.memory_limit, "D's voxel grid");
  CheckVoxelMemory(gs, options.memory_limit - VoxelizeMemoryBytes(gd), "S's voxel grid");
  {
    const double tests = SurfaceTests(scene.dynamic_mesh, gd) + SurfaceTests(scene.static_mesh, gs);
    if (gd.Count() + gs.Count() > options.max_voxels || tests > options.max_surface_tests) {
      char buf[512];
      std::snprintf(buf, sizeof buf,
                    "--voxel-size %g: %lld voxels and %.3g triangle/voxel tests, over the bounds of %lld voxels "
                    "and %.3g tests (choose a larger --voxel-size)",
                    h, static_cast<long long>(gd.Count() + gs.Count()), tests,
                    static_cast<long long>(options.max_voxels), options.max_surface_tests);
      throw InputError(buf);
    }
  }
  LogInfo("voxel size %g: S %d x %d x %d, D %d x %d x %d voxels", h, gs.dims[0], gs.dims[1], gs.dims[2], gd.dims[0],
          gd.dims[1], gd.dims[2]);
  SceneVoxels out;
  out.static_grid = VoxelizeMesh(scene.static_mesh, gs, options, &out.static_stats);
  out.dynamic_grid = VoxelizeMesh(scene.dynamic_mesh, gd, options, &out.dynamic_stats);
  if (options.shrink > 0) {
    out.dynamic_grid = ErodeVoxels(out.dynamic_grid, options.shrink);
    out.shrink = options.shrink;
  }
  return out;
}

std::vector<float> ColorValues(const VoxelGrid& grid, const TriangleMesh& mesh,
                               const std::vector<double>& deformability) {
  if (deformability.size() != mesh.vertices.size()) {
    throw InputError("labels: " + std::to_string(deformability.size()) + " values for " +
                     std::to_string(mesh.vertices.size()) + " vertices of D");
  }
  const WindingBvh bvh(mesh);
  const std::int64_t count = grid.geometry.Count();
  std::vector<float> out(static_cast<size_t>(count), 0.0f);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t v = 0; v < count; ++v) {
    if (grid.cells[v] == kVoxelEmpty) continue;
    const WindingBvh::Closest c = bvh.ClosestPoint(grid.geometry.Center(v));
    if (c.triangle < 0) continue;
    const auto& tri = mesh.triangles[c.triangle];
    const double d = c.barycentric.x() * deformability[tri[0]] + c.barycentric.y() * deformability[tri[1]] +
                     c.barycentric.z() * deformability[tri[2]];
    out[v] = static_cast<float>(std::clamp(1.0 - d, 0.0, 1.0));
  }
  return out;
}

// ---------------------------------------------------------------- artifact

namespace {

void WriteGrid(ArtifactWriter& w, const std::string& group, const VoxelGrid& grid, const std::string& units) {
  const VoxelGridGeometry& g = grid.geometry;
  w.WriteBytes(group + "/occupancy", grid.cells,
               {static_cast<size_t>(g.dims[2]), static_cast<size_t>(g.dims[1]), static_cast<size_t>(g.dims[0])});
  w.SetAttribute(group + "/occupancy", "axis_order", std::string("z,y,x (x fastest)"));
  w.SetAttribute(group + "/occupancy", "values", std::string("0 empty, 1 surface, 2 inside"));
  w.WriteDoubles(group + "/origin", {g.origin.x(), g.origin.y(), g.origin.z()}, {3});
  w.SetAttribute(group + "/origin", "units", units);
  w.WriteDoubles(group + "/spacing", {g.spacing}, {});
  w.SetAttribute(group + "/spacing", "units", units);
  w.WriteInts(group + "/dims", {g.dims[0], g.dims[1], g.dims[2]}, {3});
  w.SetAttribute(group + "/dims", "order", std::string("nx,ny,nz"));
  std::vector<double> axes;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) axes.push_back(g.axes(row, col));
  }
  w.WriteDoubles(group + "/axes", axes, {3, 3});
  w.SetAttribute(group + "/axes", "meaning", std::string("columns: the grid's x, y, z axes in mesh coordinates"));
}

VoxelGrid ReadGrid(const ArtifactReader& r, const std::string& group) {
  const std::string where = r.path().string();
  VoxelGrid grid;
  const Array<double> origin = r.ReadDoubles(group + "/origin", 1);
  const Array<double> spacing = r.ReadDoubles(group + "/spacing");
  const Array<std::int64_t> dims = r.ReadInts(group + "/dims", 1);
  if (origin.data.size() != 3) throw InputErrorAt(where, "dataset '" + group + "/origin' must hold 3 numbers");
  if (dims.data.size() != 3) throw InputErrorAt(where, "dataset '" + group + "/dims' must hold 3 numbers");
  if (spacing.data.size() != 1 || !(spacing.data[0] > 0) || !std::isfinite(spacing.data[0])) {
    throw InputErrorAt(where, "dataset '" + group + "/spacing' must be one positive number");
  }
  grid.geometry.origin = {origin.data[0], origin.data[1], origin.data[2]};
  if (!grid.geometry.origin.allFinite()) throw InputErrorAt(where, "dataset '" + group + "/origin' is not finite");
  grid.geometry.spacing = spacing.data[0];
  if (r.Has(group + "/axes")) {  // absent in artifacts written before turned grids: identity
    const Array<double> axes = r.ReadDoubles(group + "/axes", 2);
    if (axes.dims != std::vector<size_t>{3, 3}) throw InputErrorAt(where, "dataset '" + group + "/axes' must be 3 x 3");
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) grid.geometry.axes(row, col) = axes.data[3 * row + col];
    }
    const Eigen::Matrix3d& a = grid.geometry.axes;
    if (!a.allFinite() || !(a.transpose() * a).isIdentity(1e-9) || !(a.determinant() > 0)) {
      throw InputErrorAt(where, "dataset '" + group + "/axes' is not a rotation");
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (dims.data[k] < 1 || dims.data[k] > 1000000000) {
      throw InputErrorAt(where, "dataset '" + group + "/dims' holds an invalid size");
    }
    grid.geometry.dims[k] = static_cast<int>(dims.data[k]);
  }
  // The far corner must be finite too (origin 1e300, spacing 1e300 are
  // each finite but the grid's extent is not).
  const Eigen::Vector3d extent = grid.geometry.spacing * Eigen::Vector3d(dims.data[0], dims.data[1], dims.data[2]);
  if (!(grid.geometry.origin + extent).allFinite() || !(extent.maxCoeff() < 1e300)) {
    throw InputErrorAt(where, "group '" + group + "' describes a grid of non-finite extent");
  }
  Array<std::uint8_t> cells = r.ReadBytes(group + "/occupancy", 3);
  if (cells.dims != std::vector<size_t>{static_cast<size_t>(grid.geometry.dims[2]),
                                        static_cast<size_t>(grid.geometry.dims[1]),
                                        static_cast<size_t>(grid.geometry.dims[0])}) {
    throw InputErrorAt(where,
                       "dataset '" + group + "/occupancy' does not match '" + group + "/dims' (expected [nz, ny, nx])");
  }
  for (std::uint8_t c : cells.data) {
    if (c > kVoxelInside)
      throw InputErrorAt(where, "dataset '" + group + "/occupancy' holds a value other than 0, 1, 2");
  }
  grid.cells = std::move(cells.data);
  return grid;
}

}  // namespace

void WriteVoxelArtifact(const std::filesystem::path& file, const SceneVoxels& voxels, const VoxelArtifactInfo& info,
                        const Provenance& provenance) {
  ArtifactWriter w(file, kVoxelsSchema, kVoxelsSchemaVersion, provenance);
  WriteGrid(w, "static", voxels.static_grid, info.units);
  WriteGrid(w, "dynamic", voxels.dynamic_grid, info.units);
  w.WriteDoubles("dynamic/shrink", {voxels.shrink}, {});
  w.SetAttribute("dynamic/shrink", "units", info.units);
  w.WriteInts("stats/static_surface", {voxels.static_stats.surface}, {});
  w.WriteInts("stats/static_inside", {voxels.static_stats.inside}, {});
  w.WriteInts("stats/dynamic_surface", {voxels.dynamic_grid.Count(kVoxelSurface)}, {});
  w.WriteInts("stats/dynamic_inside", {voxels.dynamic_grid.Count(kVoxelInside)}, {});
  w.WriteDoubles("stats/time_s", {voxels.static_stats.time_s + voxels.dynamic_stats.time_s}, {});
  w.SetAttribute("stats/time_s", "units", std::string("s"));
  w.SetAttribute("", "scene", info.scene);
  w.SetAttribute("", "units", info.units);
  w.Commit();
}

SceneVoxels ReadVoxelArtifact(const std::filesystem::path& file, VoxelArtifactInfo* info) {
  ArtifactReader r(file, kVoxelsSchema, kVoxelsSchemaVersion);
  SceneVoxels out;
  out.static_grid = ReadGrid(r, "static");
  out.dynamic_grid = ReadGrid(r, "dynamic");
  if (std::abs(out.static_grid.geometry.spacing - out.dynamic_grid.geometry.spacing) >
      1e-12 * out.static_grid.geometry.spacing) {
    throw InputErrorAt(file.string(), "S's and D's grids have different voxel sizes");
  }
  const Array<double> shrink = r.ReadDoubles("dynamic/shrink");
  if (shrink.data.size() != 1) throw InputErrorAt(file.string(), "dataset 'dynamic/shrink' must be a scalar");
  out.shrink = shrink.data[0];
  if (!(std::isfinite(out.shrink) && out.shrink >= 0)) {
    throw InputErrorAt(file.string(), "dataset 'dynamic/shrink' must be a finite number >= 0");
  }
  out.static_stats.surface = out.static_grid.Count(kVoxelSurface);
  out.static_stats.inside = out.static_grid.Count(kVoxelInside);
  out.dynamic_stats.surface = out.dynamic_grid.Count(kVoxelSurface);
  out.dynamic_stats.inside = out.dynamic_grid.Count(kVoxelInside);
  if (info != nullptr) {
    info->scene = r.ReadStringAttribute("", "scene");
    info->units = r.ReadStringAttribute("", "units");
  }
  return out;
}

}  // namespace ausbau
