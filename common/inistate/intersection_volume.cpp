#include "inistate/intersection_volume.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace ausbau {
namespace {

constexpr int kBrickShift = 1;  // 2 x 2 x 2 voxels per brick
constexpr int kGroupShift = 3;  // 8 x 8 x 8 voxels (up to 4 x 4 x 4 bricks) per group

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

// A colour value as alg. 12 sums it: +infinity (a voxel that must not
// intersect S) is kept, the rest clamped to colorValue's range.
float Weight(float color) {
  return color == std::numeric_limits<float>::infinity() ? color : std::clamp(color, 0.0f, 1.0f);
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
    std::int32_t begin, end;  // voxels (bricks for a group)
    Eigen::Vector3d center;   // in D's index space
    double radius;            // in D's voxels
  };
  std::vector<Brick> bricks;
  std::vector<Brick> groups;      // of bricks: a first, coarser cull
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
  // D's voxels sorted by group, brick and raster order.
  const VoxelGridGeometry& g = dynamic_grid.geometry;
  const int bx = (g.dims[0] >> kBrickShift) + 1, by = (g.dims[1] >> kBrickShift) + 1;
  const int gx = (g.dims[0] >> kGroupShift) + 1, gy = (g.dims[1] >> kGroupShift) + 1;
  struct Entry {
    std::int64_t group, brick, cell;
    bool operator<(const Entry& o) const {
      return group != o.group ? group < o.group : brick != o.brick ? brick < o.brick : cell < o.cell;
    }
  };
  std::vector<Entry> order;
  for (int k = 0; k < g.dims[2]; ++k) {
    for (int j = 0; j < g.dims[1]; ++j) {
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::int64_t cell = g.Index(i, j, k);
        if (dynamic_grid.cells[cell] == kVoxelEmpty) continue;
        const std::int64_t brick = (std::int64_t{k >> kBrickShift} * by + (j >> kBrickShift)) * bx + (i >> kBrickShift);
        const std::int64_t group = (std::int64_t{k >> kGroupShift} * gy + (j >> kGroupShift)) * gx + (i >> kGroupShift);
        order.push_back({group, brick, cell});
      }
    }
  }
  std::sort(order.begin(), order.end());
  if (order.size() > static_cast<size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw InputError("intersection volume: D has too many voxels");
  }
  std::vector<std::int32_t> compact(static_cast<size_t>(g.Count()), -1);
  for (size_t n = 0; n < order.size(); ++n) {
    const std::int64_t cell = order[n].cell;
    compact[cell] = static_cast<std::int32_t>(n);
    const Eigen::Vector3i c = g.Cell(cell);
    data->cells.push_back({c.x(), c.y(), c.z()});
    data->weight.push_back(color_values.empty() ? 1.0f : Weight(color_values[cell]));
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
  // A ball around voxels [begin, end) of the list.
  auto ball = [&](size_t begin, size_t end) {
    Aabb box;
    for (size_t n = begin; n < end; ++n) {
      const auto& c = data->cells[n];
      box.Extend(Eigen::Vector3d(c[0], c[1], c[2]));
    }
    Data::Brick brick;
    brick.center = box.Center();
    brick.radius = 0;
    for (size_t n = begin; n < end; ++n) {
      const auto& c = data->cells[n];
      brick.radius = std::max(brick.radius, (Eigen::Vector3d(c[0], c[1], c[2]) - brick.center).norm());
    }
    return brick;
  };
  for (size_t group_begin = 0; group_begin < order.size();) {
    size_t group_end = group_begin;
    while (group_end < order.size() && order[group_end].group == order[group_begin].group) ++group_end;
    Data::Brick group = ball(group_begin, group_end);
    group.begin = static_cast<std::int32_t>(data->bricks.size());
    for (size_t begin = group_begin; begin < group_end;) {
      size_t end = begin;
      while (end < group_end && order[end].brick == order[begin].brick) ++end;
      Data::Brick brick = ball(begin, end);
      brick.begin = static_cast<std::int32_t>(begin);
      brick.end = static_cast<std::int32_t>(end);
      data->bricks.push_back(brick);
      begin = end;
    }
    group.end = static_cast<std::int32_t>(data->bricks.size());
    data->groups.push_back(group);
    group_begin = group_end;
  }
  data_ = std::move(data);
  buffers_ = std::make_unique<Buffers>();
}

IntersectionVolume::IntersectionVolume(std::shared_ptr<const Data> data)
    : data_(std::move(data)), buffers_(std::make_unique<Buffers>()) {}
IntersectionVolume::IntersectionVolume(IntersectionVolume&&) noexcept = default;
IntersectionVolume& IntersectionVolume::operator=(IntersectionVolume&&) noexcept = default;
IntersectionVolume::~IntersectionVolume() = default;

IntersectionVolume IntersectionVolume::Clone() const {
  IntersectionVolume clone(data_);
  clone.rigid_guard_ = rigid_guard_;
  return clone;
}

IntersectionVolume IntersectionVolume::Reweighted(const std::vector<float>& color_values) const {
  if (static_cast<std::int64_t>(color_values.size()) != data_->d_geometry.Count()) {
    throw InputError("intersection volume: " + std::to_string(color_values.size()) + " colour values for " +
                     std::to_string(data_->d_geometry.Count()) + " voxels of D");
  }
  auto data = std::make_shared<Data>(*data_);
  for (std::size_t n = 0; n < data->cells.size(); ++n) {
    const auto& c = data->cells[n];
    data->weight[n] = Weight(color_values[data->d_geometry.Index(c[0], c[1], c[2])]);
  }
  data->color_grid = color_values;
  IntersectionVolume out(std::move(data));
  out.rigid_guard_ = rigid_guard_;
  return out;
}

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

// Kept as one function (about 160 lines) on purpose: the planners' hottest
// query (every validity check of a volume mode). Its traversal keeps the
// running sum, the early exit against tau and the per-part bookkeeping in
// registers; its steps are commented below.
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
  // (Both grids may be turned: D's lies in D's principal frame, S's in that
  // frame at the installed pose; voxel_grid.h.)
  const Eigen::Matrix3d to_s = d.s_geometry.axes.transpose();
  const Eigen::Matrix3d m = to_s * rotation * d.d_geometry.axes * (hd / hs);
  const Eigen::Vector3d first_center = d.d_geometry.Center(0, 0, 0);
  const Eigen::Vector3d g0 = to_s * (rotation * (first_center - d.reference_point) + pose.t - d.s_geometry.origin) / hs;
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
    if (static_cast<unsigned>(i) >= static_cast<unsigned>(snx) ||
        static_cast<unsigned>(j) >= static_cast<unsigned>(sny) ||
        static_cast<unsigned>(k) >= static_cast<unsigned>(snz)) {
      return false;
    }
    return distance[k * splane + std::int64_t{j} * snx + i] == 0;
  };

  const double scale = hd / hs;
  const bool record = query != nullptr && query->record_cells;
  double best = 0;  // largest component value (count or weight sum)
  std::int64_t best_voxels = 0;
  int components = 0;
  bool early_out = false;
  const double voxel_volume = hd * hd * hd;
  if (record) b.best.clear();

  // True when no occupied S voxel lies within reach of the ball: a voxel
  // centre p within r of the centre c lies in a cell at most floor(r) + 1
  // cells (chessboard) from c's cell.
  auto culled_ball = [&](const Data::Brick& ball) {
    const Eigen::Vector3d c = g0 + m * ball.center;
    const double fx = std::floor(c.x()), fy = std::floor(c.y()), fz = std::floor(c.z());
    const int reach = static_cast<int>(std::floor(ball.radius * scale)) + 1;
    if (!(std::abs(fx) < 1e9 && std::abs(fy) < 1e9 && std::abs(fz) < 1e9)) return true;  // far away (or NaN)
    const int ci = static_cast<int>(fx), cj = static_cast<int>(fy), ck = static_cast<int>(fz);
    const int ii = std::clamp(ci, 0, snx - 1), jj = std::clamp(cj, 0, sny - 1), kk = std::clamp(ck, 0, snz - 1);
    const int outside = std::max({std::abs(ci - ii), std::abs(cj - jj), std::abs(ck - kk)});
    if (outside > reach) return true;
    // Triangle inequality: from c's cell, occupied cells are at least
    // (distance at the clamped cell) - outside away.
    return distance[kk * splane + std::int64_t{jj} * snx + ii] - outside > reach;
  };

  // Tests the voxels of one brick, flood-filling from each intersecting one;
  // false after an early out.
  auto scan = [&](const Data::Brick& brick) {
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
        if (weighted && sum * voxel_volume > tau) {  // alg. 12 with the early out of 5.4.4
          early_out = true;
          break;
        }
      }
      ++components;
      visited += static_cast<std::int64_t>(b.queue.size());
      if (early_out || sum > best) {
        best = sum;
        best_voxels = static_cast<std::int64_t>(b.queue.size());
        if (record) b.best = b.queue;
      }
      if (early_out) return false;
    }
    return true;
  };

  for (const Data::Brick& group : d.groups) {
    if (culled_ball(group)) {
      culled += group.end - group.begin;
      continue;
    }
    bool go_on = true;
    for (std::int32_t i = group.begin; i < group.end && go_on; ++i) {
      if (culled_ball(d.bricks[i])) {
        ++culled;
      } else {
        go_on = scan(d.bricks[i]);
      }
    }
    if (!go_on) break;
  }

  double value;
  if (mode == Mode::kIv) {
    value = intersecting * voxel_volume;
    best_voxels = intersecting;
  } else {
    value = best * voxel_volume;
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

double IntersectionVolume::Measure(VolumeMeasure measure, const Pose& pose, double tau, VolumeQuery* query) {
  if (rigid_guard_ && !rigid_guard_->IsValid(pose)) {
    if (query != nullptr) {
      const bool record = query->record_cells;
      *query = VolumeQuery{};
      query->record_cells = record;
      query->value = std::numeric_limits<double>::infinity();
    }
    return std::numeric_limits<double>::infinity();
  }
  switch (measure) {
    case VolumeMeasure::kIv: return Iv(pose, query);
    case VolumeMeasure::kMliv: return Mliv(pose, query);
    case VolumeMeasure::kLabeledMliv: return LabeledMliv(pose, tau, query);
  }
  return LabeledMliv(pose, tau, query);
}

VolumeValidity::VolumeValidity(const IntersectionVolume& volume, VolumeMeasure measure, double tau)
    : prototype_(&volume), measure_(measure), tau_(tau) {}
VolumeValidity::~VolumeValidity() = default;

bool VolumeValidity::CheckValid(const Pose& pose) const {
  std::unique_ptr<IntersectionVolume> volume;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pool_.empty()) {
      volume = std::move(pool_.back());
      pool_.pop_back();
    }
  }
  if (!volume) volume = std::make_unique<IntersectionVolume>(prototype_->Clone());
  const bool valid = volume->Measure(measure_, pose, tau_) <= tau_;
  std::lock_guard<std::mutex> lock(mutex_);
  pool_.push_back(std::move(volume));
  return valid;
}

}  // namespace ausbau
