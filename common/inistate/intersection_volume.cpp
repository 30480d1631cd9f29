#include "inistate/intersection_volume.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace ausbau {
namespace {

constexpr int kBrickShift = 2;  // 4 x 4 x 4 voxels per brick

// Chessboard (L-infinity, 26-neighbour) distance in voxels from each cell to
// the nearest occupied cell, capped at 255: the two-pass chamfer transform
// with unit weights, which is exact for this metric.
std::vector<std::uint8_t> ChessboardDistance(const VoxelGrid& grid) {
  const int nx = grid.geometry.dims[0], ny = grid.geometry.dims[1], nz = grid.geometry.dims[2];
  std::vector<std::uint8_t> d(grid.cells.size());
  for (size_t v = 0; v < d.size(); ++v) d[v] = grid.cells[v] != kVoxelEmpty ? 0 : 255;
  const std::int64_t sx = 1, sy = nx, sz = std::int64_t{nx} * ny;
  auto relax = [&](std::int64_t v, int i, int j, int k, int direction) {
    int best = d[v];
    if (best == 0) return;
    // The 13 neighbours before (direction +1) or after (-1) v in raster order.
    for (int dk = -1; dk <= 0; ++dk) {
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          if (dk == 0 && (dj > 0 || (dj == 0 && di >= 0))) continue;
          const int ii = i + direction * di, jj = j + direction * dj, kk = k + direction * dk;
          if (ii < 0 || jj < 0 || kk < 0 || ii >= nx || jj >= ny || kk >= nz) continue;
          const int n = d[v + direction * (di * sx + dj * sy + dk * sz)] + 1;
          if (n < best) best = n;
        }
      }
    }
    d[v] = static_cast<std::uint8_t>(std::min(best, 255));
  };
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) relax(grid.geometry.Index(i, j, k), i, j, k, +1);
    }
  }
  for (int k = nz - 1; k >= 0; --k) {
    for (int j = ny - 1; j >= 0; --j) {
      for (int i = nx - 1; i >= 0; --i) relax(grid.geometry.Index(i, j, k), i, j, k, -1);
    }
  }
  return d;
}

}  // namespace

struct IntersectionVolume::Data {
  // S.
  VoxelGridGeometry s_geometry;
  std::vector<std::uint8_t> s_distance;  // 0 = occupied
  // D, as a compact list sorted by brick.
  VoxelGridGeometry d_geometry;
  Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();
  std::vector<std::array<std::int32_t, 3>> cells;      // (i, j, k) in D's grid
  std::vector<std::array<std::int32_t, 6>> neighbors;  // -1: none
  std::vector<float> weight;                           // colorValue
  struct Brick {
    std::int32_t begin, end;
    Eigen::Vector3d center;  // in D's index space
    double radius;           // in D's voxels
  };
  std::vector<Brick> bricks;
  std::vector<float> color_grid;  // per cell of D's grid (for color_value())
};

struct IntersectionVolume::Buffers {
  std::vector<std::uint32_t> stamp;  // (generation << 2) | state; state 1 = miss, 2 = intersecting
  std::uint32_t generation = 0;
  std::vector<std::int32_t> queue, best;
};

IntersectionVolume::IntersectionVolume(const VoxelGrid& static_grid, const VoxelGrid& dynamic_grid,
                                       const Eigen::Vector3d& reference_point, const std::vector<float>& color_values) {
  if (static_cast<std::int64_t>(static_grid.cells.size()) != static_grid.geometry.Count() ||
      static_cast<std::int64_t>(dynamic_grid.cells.size()) != dynamic_grid.geometry.Count()) {
    throw InputError("intersection volume: a voxel grid's cells do not match its dimensions");
  }
  if (!color_values.empty() && static_cast<std::int64_t>(color_values.size()) != dynamic_grid.geometry.Count()) {
    throw InputError("intersection volume: " + std::to_string(color_values.size()) + " colour values for " +
                     std::to_string(dynamic_grid.geometry.Count()) + " cells of D's grid");
  }
  auto data = std::make_shared<Data>();
  data->s_geometry = static_grid.geometry;
  data->s_distance = ChessboardDistance(static_grid);
  data->d_geometry = dynamic_grid.geometry;
  data->reference_point = reference_point;
  if (color_values.empty()) {  // without labels every voxel is rigid
    data->color_grid.resize(dynamic_grid.cells.size());
    for (size_t v = 0; v < dynamic_grid.cells.size(); ++v) data->color_grid[v] = dynamic_grid.cells[v] != kVoxelEmpty;
  } else {
    data->color_grid = color_values;
  }

  // D's voxels sorted by brick, then in raster order within a brick.
  const VoxelGridGeometry& g = dynamic_grid.geometry;
  const int bx = (g.dims[0] >> kBrickShift) + 1, by = (g.dims[1] >> kBrickShift) + 1;
  std::vector<std::pair<std::int64_t, std::int64_t>> order;  // (brick, cell)
  for (int k = 0; k < g.dims[2]; ++k) {
    for (int j = 0; j < g.dims[1]; ++j) {
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::int64_t cell = g.Index(i, j, k);
        if (dynamic_grid.cells[cell] == kVoxelEmpty) continue;
        const std::int64_t brick =
            (std::int64_t{k >> kBrickShift} * by + (j >> kBrickShift)) * bx + (i >> kBrickShift);
        order.emplace_back(brick, cell);
      }
    }
  }
  std::sort(order.begin(), order.end());
  if (order.size() > static_cast<size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw InputError("intersection volume: D has too many voxels");
  }
  std::vector<std::int32_t> compact(static_cast<size_t>(g.Count()), -1);
  for (size_t n = 0; n < order.size(); ++n) {
    const std::int64_t cell = order[n].second;
    compact[cell] = static_cast<std::int32_t>(n);
    const int i = static_cast<int>(cell % g.dims[0]), j = static_cast<int>((cell / g.dims[0]) % g.dims[1]),
              k = static_cast<int>(cell / (std::int64_t{g.dims[0]} * g.dims[1]));
    data->cells.push_back({i, j, k});
    data->weight.push_back(color_values.empty() ? 1.0f : std::clamp(color_values[cell], 0.0f, 1.0f));
  }
  data->neighbors.resize(order.size());
  static const int kOffsets[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  for (size_t n = 0; n < order.size(); ++n) {
    const auto& c = data->cells[n];
    for (int e = 0; e < 6; ++e) {
      const int i = c[0] + kOffsets[e][0], j = c[1] + kOffsets[e][1], k = c[2] + kOffsets[e][2];
      data->neighbors[n][e] = g.Contains(i, j, k) ? compact[g.Index(i, j, k)] : -1;
    }
  }
  for (size_t begin = 0; begin < order.size();) {
    size_t end = begin;
    Aabb box;
    while (end < order.size() && order[end].first == order[begin].first) {
      const auto& c = data->cells[end];
      box.Extend(Eigen::Vector3d(c[0], c[1], c[2]));
      ++end;
    }
    Data::Brick brick;
    brick.begin = static_cast<std::int32_t>(begin);
    brick.end = static_cast<std::int32_t>(end);
    brick.center = box.Center();
    brick.radius = 0;
    for (size_t n = begin; n < end; ++n) {
      const auto& c = data->cells[n];
      brick.radius = std::max(brick.radius, (Eigen::Vector3d(c[0], c[1], c[2]) - brick.center).norm());
    }
    data->bricks.push_back(brick);
    begin = end;
  }
  data_ = std::move(data);
  buffers_ = std::make_unique<Buffers>();
}

IntersectionVolume::IntersectionVolume(std::shared_ptr<const Data> data)
    : data_(std::move(data)), buffers_(std::make_unique<Buffers>()) {}
IntersectionVolume::IntersectionVolume(IntersectionVolume&&) noexcept = default;
IntersectionVolume& IntersectionVolume::operator=(IntersectionVolume&&) noexcept = default;
IntersectionVolume::~IntersectionVolume() = default;

IntersectionVolume IntersectionVolume::Clone() const { return IntersectionVolume(data_); }

std::int64_t IntersectionVolume::voxel_count() const { return static_cast<std::int64_t>(data_->cells.size()); }
double IntersectionVolume::voxel_volume() const { return data_->d_geometry.VoxelVolume(); }
const Eigen::Vector3d& IntersectionVolume::reference_point() const { return data_->reference_point; }
float IntersectionVolume::color_value(int i, int j, int k) const {
  if (!data_->d_geometry.Contains(i, j, k)) return 0.0f;
  return data_->color_grid[data_->d_geometry.Index(i, j, k)];
}

double IntersectionVolume::Iv(const Pose& pose, VolumeQuery* query) { return Run(pose, Mode::kIv, 0, query); }
double IntersectionVolume::Mliv(const Pose& pose, VolumeQuery* query) { return Run(pose, Mode::kMliv, 0, query); }
double IntersectionVolume::LabeledMliv(const Pose& pose, double tau, VolumeQuery* query) {
  return Run(pose, Mode::kLabeled, tau, query);
}

double IntersectionVolume::Run(const Pose& pose, Mode mode, double tau, VolumeQuery* query) {
  const Data& d = *data_;
  Buffers& b = *buffers_;
  const size_t n = d.cells.size();
  if (b.stamp.size() != n) {
    b.stamp.assign(n, 0);
    b.generation = 0;
  }
  if (++b.generation >= (1u << 30)) {
    std::fill(b.stamp.begin(), b.stamp.end(), 0);
    b.generation = 1;
  }
  const std::uint32_t miss = (b.generation << 2) | 1, hit = (b.generation << 2) | 2;

  // D index (i, j, k) -> continuous S index: g0 + m (i, j, k).
  const Eigen::Matrix3d rotation = pose.q.normalized().toRotationMatrix();
  const double hs = d.s_geometry.spacing, hd = d.d_geometry.spacing;
  const Eigen::Matrix3d m = rotation * (hd / hs);
  const Eigen::Vector3d first_center = d.d_geometry.origin + Eigen::Vector3d::Constant(0.5 * hd);
  const Eigen::Vector3d g0 = (rotation * (first_center - d.reference_point) + pose.t - d.s_geometry.origin) / hs;
  const int snx = d.s_geometry.dims[0], sny = d.s_geometry.dims[1], snz = d.s_geometry.dims[2];
  const std::int64_t splane = std::int64_t{snx} * sny;
  const std::uint8_t* distance = d.s_distance.data();

  std::int64_t tested = 0, visited = 0, intersecting = 0, culled = 0;
  auto intersects = [&](std::int32_t v) {
    ++tested;
    const auto& c = d.cells[v];
    const Eigen::Vector3d s = g0 + m * Eigen::Vector3d(c[0], c[1], c[2]);
    const int i = static_cast<int>(std::floor(s.x())), j = static_cast<int>(std::floor(s.y())),
              k = static_cast<int>(std::floor(s.z()));
    if (static_cast<unsigned>(i) >= static_cast<unsigned>(snx) || static_cast<unsigned>(j) >= static_cast<unsigned>(sny) ||
        static_cast<unsigned>(k) >= static_cast<unsigned>(snz)) {
      return false;
    }
    return distance[k * splane + std::int64_t{j} * snx + i] == 0;
  };

  const double scale = hd / hs;
  const bool record = query != nullptr && query->record_cells;
  double best = 0;             // largest component value (count or weight sum)
  std::int64_t best_voxels = 0;
  int components = 0;
  bool early_out = false;
  double early_value = 0;
  if (record) b.best.clear();

  for (const Data::Brick& brick : d.bricks) {
    // Cull: no occupied S voxel within reach of the brick's ball.
    const Eigen::Vector3d c = g0 + m * brick.center;
    const int ci = static_cast<int>(std::floor(c.x())), cj = static_cast<int>(std::floor(c.y())),
              ck = static_cast<int>(std::floor(c.z()));
    const int reach = static_cast<int>(std::floor(brick.radius * scale)) + 1;
    const int ii = std::clamp(ci, 0, snx - 1), jj = std::clamp(cj, 0, sny - 1), kk = std::clamp(ck, 0, snz - 1);
    const int outside = std::max({std::abs(ci - ii), std::abs(cj - jj), std::abs(ck - kk)});
    const int near = distance[kk * splane + std::int64_t{jj} * snx + ii];
    if (outside > reach || near - outside > reach) {
      ++culled;
      continue;
    }
    for (std::int32_t v = brick.begin; v < brick.end; ++v) {
      if ((b.stamp[v] >> 2) == b.generation) continue;  // tested already
      if (!intersects(v)) {
        b.stamp[v] = miss;
        continue;
      }
      b.stamp[v] = hit;
      ++intersecting;
      if (mode == Mode::kIv) {
        if (record) b.best.push_back(v);
        continue;
      }
      // Flood fill of the component through D's 6-neighbours (alg. 11).
      const bool weighted = mode == Mode::kLabeled;
      b.queue.clear();
      b.queue.push_back(v);
      double sum = weighted ? d.weight[v] : 1.0;
      for (size_t head = 0; head < b.queue.size(); ++head) {
        const std::int32_t u = b.queue[head];
        for (std::int32_t w : d.neighbors[u]) {
          if (w < 0 || (b.stamp[w] >> 2) == b.generation) continue;
          if (!intersects(w)) {
            b.stamp[w] = miss;
            continue;
          }
          b.stamp[w] = hit;
          ++intersecting;
          b.queue.push_back(w);
          sum += weighted ? d.weight[w] : 1.0;
        }
        if (weighted && sum * hd * hd * hd > tau) {  // alg. 12 with the early out of 5.4.4
          early_out = true;
          early_value = sum;
          break;
        }
      }
      ++components;
      visited += static_cast<std::int64_t>(b.queue.size());
      if (early_out || sum > best) {
        best = early_out ? early_value : sum;
        best_voxels = static_cast<std::int64_t>(b.queue.size());
        if (record) b.best = b.queue;
      }
      if (early_out) break;
    }
    if (early_out) break;
  }

  const double volume = hd * hd * hd;
  double value;
  if (mode == Mode::kIv) {
    value = intersecting * volume;
    best_voxels = intersecting;
  } else {
    value = best * volume;
  }
  if (query != nullptr) {
    query->value = value;
    query->voxels = best_voxels;
    query->intersecting = intersecting;
    query->components = components;
    query->early_out = early_out;
    query->tested = tested;
    query->visited = visited;
    query->bricks_culled = culled;
    query->bricks = static_cast<std::int64_t>(d.bricks.size());
    query->cells.clear();
    if (record) {
      for (std::int32_t v : b.best) query->cells.emplace_back(d.cells[v][0], d.cells[v][1], d.cells[v][2]);
    }
  }
  return value;
}

LabeledMlivValidity::LabeledMlivValidity(const IntersectionVolume& volume, double tau)
    : prototype_(&volume), tau_(tau) {}
LabeledMlivValidity::~LabeledMlivValidity() = default;

bool LabeledMlivValidity::CheckValid(const Pose& pose) const {
  std::unique_ptr<IntersectionVolume> volume;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pool_.empty()) {
      volume = std::move(pool_.back());
      pool_.pop_back();
    }
  }
  if (!volume) volume = std::make_unique<IntersectionVolume>(prototype_->Clone());
  const bool valid = volume->LabeledMliv(pose, tau_) <= tau_;
  std::lock_guard<std::mutex> lock(mutex_);
  pool_.push_back(std::move(volume));
  return valid;
}

}  // namespace ausbau
