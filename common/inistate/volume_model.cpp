#include "inistate/volume_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

#include "collision/rigid_depth.h"
#include "core/error.h"
#include "core/log.h"
#include "geometry/weld.h"

namespace ausbau {

VolumeMeasure MeasureOf(ValidityMode mode) {
  switch (mode) {
    case ValidityMode::kMliv: return VolumeMeasure::kMliv;
    case ValidityMode::kLabeledMliv:
    case ValidityMode::kLabeledMlivUnguarded: return VolumeMeasure::kLabeledMliv;
    default: return VolumeMeasure::kIv;
  }
}

bool NeedsLabels(ValidityMode mode) {
  return mode == ValidityMode::kLabeledMliv || mode == ValidityMode::kLabeledMlivUnguarded;
}

namespace {

int FindRoot(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// Connected components of D's triangles over shared vertex positions (CAD
// exports often duplicate vertices along seams), numbered by first triangle.
std::vector<int> TriangleParts(const TriangleMesh& mesh, int* count) {
  const std::vector<int> vertex_id = WeldExactPositions(mesh.vertices);
  // Welded indices count up from 0: their number is the largest plus one.
  const int welded_count = vertex_id.empty() ? 0 : *std::max_element(vertex_id.begin(), vertex_id.end()) + 1;
  std::vector<int> parent(welded_count);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& t : mesh.triangles) {
    const int a = FindRoot(parent, vertex_id[t[0]]);
    for (int k = 1; k < 3; ++k) {
      const int b = FindRoot(parent, vertex_id[t[k]]);
      if (a != b) parent[b] = a;
    }
  }
  std::vector<int> number(welded_count, -1);
  std::vector<int> part(mesh.triangles.size());
  *count = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int root = FindRoot(parent, vertex_id[mesh.triangles[t][0]]);
    if (number[root] < 0) number[root] = (*count)++;
    part[t] = number[root];
  }
  return part;
}

double PsiOf(const VoxelGrid& grid, const std::vector<float>& colors) {
  const VoxelGridGeometry& g = grid.geometry;
  const double margin = 2.0 * g.spacing;
  if (colors.empty()) return margin;
  const std::int64_t n = g.Count();
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(n), 0);
  std::vector<std::int64_t> stack;
  std::int64_t best_count = 0;
  double best_extent = 0;
  auto deformable = [&](std::int64_t v) {
    return grid.cells[v] != kVoxelEmpty && colors[v] < VolumeModel::kDeformableColor;
  };
  for (std::int64_t start = 0; start < n; ++start) {
    if (seen[start] || !deformable(start)) continue;
    seen[start] = 1;
    stack.assign(1, start);
    std::int64_t count = 0;
    Eigen::Vector3i lo(g.dims[0], g.dims[1], g.dims[2]), hi(-1, -1, -1);
    while (!stack.empty()) {
      const std::int64_t v = stack.back();
      stack.pop_back();
      ++count;
      const Eigen::Vector3i cell = g.Cell(v);
      const int i = cell.x(), j = cell.y(), k = cell.z();
      lo = lo.cwiseMin(cell);
      hi = hi.cwiseMax(cell);
      const int neighbours[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
      for (const auto& d : neighbours) {
        const int a = i + d[0], b = j + d[1], c = k + d[2];
        if (!g.Contains(a, b, c)) continue;
        const std::int64_t w = g.Index(a, b, c);
        if (seen[w] || !deformable(w)) continue;
        seen[w] = 1;
        stack.push_back(w);
      }
    }
    if (count > best_count) {
      best_count = count;
      best_extent = ((hi - lo).array() + 1).maxCoeff() * g.spacing;
    }
  }
  return best_extent + margin;
}

// The fastener guard (volume_model.h): D's voxels (`grid`) farther than
// `reach` from every voxel of D intersecting S at `start` (`volume`'s IV
// cells), the distance measured through D's voxels (26-neighbour steps of
// 1, sqrt 2, sqrt 3 voxels; Dijkstra, stopped at `reach`), get colorValue
// +infinity.
void GuardFasteners(const VoxelGrid& grid, IntersectionVolume& volume, const Pose& start, double reach,
                    std::vector<float>* colors, std::int64_t* start_voxels, std::int64_t* reach_voxels) {
  const VoxelGridGeometry& g = grid.geometry;
  VolumeQuery at_start;
  at_start.record_cells = true;
  volume.Iv(start, &at_start);  // IV: all intersecting voxels, whatever their colours

  const float radius = static_cast<float>(reach / g.spacing);
  std::vector<float> distance(static_cast<std::size_t>(g.Count()), std::numeric_limits<float>::infinity());
  using Item = std::pair<float, std::int64_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (const Eigen::Vector3i& c : at_start.cells) {
    const std::int64_t v = g.Index(c.x(), c.y(), c.z());
    distance[v] = 0;
    queue.push({0.0f, v});
  }
  const float step[4] = {0.0f, 1.0f, std::sqrt(2.0f), std::sqrt(3.0f)};
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;  // a stale entry
    const Eigen::Vector3i cell = g.Cell(v);
    const int i = cell.x(), j = cell.y(), k = cell.z();
    for (int a = -1; a <= 1; ++a) {
      for (int b = -1; b <= 1; ++b) {
        for (int c = -1; c <= 1; ++c) {
          if (!g.Contains(i + a, j + b, k + c)) continue;
          const std::int64_t w = g.Index(i + a, j + b, k + c);
          if (grid.cells[w] == kVoxelEmpty) continue;
          const float through = d + step[std::abs(a) + std::abs(b) + std::abs(c)];
          if (through < distance[w] && through <= radius) {
            distance[w] = through;
            queue.push({through, w});
          }
        }
      }
    }
  }
  *start_voxels = static_cast<std::int64_t>(at_start.cells.size());
  *reach_voxels = 0;
  for (std::int64_t v = 0; v < g.Count(); ++v) {
    if (grid.cells[v] == kVoxelEmpty) continue;
    if (distance[v] <= radius) {
      ++*reach_voxels;
    } else {
      (*colors)[v] = std::numeric_limits<float>::infinity();
    }
  }
}

}  // namespace

VolumeModel::VolumeModel(const PlanningProblem& problem, const TriangleMesh& dynamic_mesh, SceneVoxels voxels,
                         const std::vector<double>& deformability, ValidityMode mode)
    : mode_(mode), voxels_(std::move(voxels)) {
  if (!IsVolumeValidity(mode))
    throw std::logic_error("VolumeModel: " + ValidityModeName(mode) + " is not a volume mode");
  if (NeedsLabels(mode) && deformability.empty()) {
    throw InputError("--validity " + ValidityModeName(mode) + " needs D's labels (ausbau-pbd-label, --labels)");
  }
  if (!deformability.empty()) colors_ = ColorValues(voxels_.dynamic_grid, dynamic_mesh, deformability);
  psi_ = PsiOf(voxels_.dynamic_grid, colors_);  // of D as it is, before any shrinking

  if (mode == ValidityMode::kShrink) {
    // The smallest erosion (whole voxels) that frees the start pose, as long
    // as something of D is left.
    const VoxelGrid original = voxels_.dynamic_grid;
    const double h = voxel_size();
    for (int k = 1;; ++k) {
      voxels_.dynamic_grid = ErodeVoxels(original, k * h);
      if (voxels_.dynamic_grid.CountOccupied() == 0) {
        throw InputError("--validity shrink: D vanishes (eroded by " + std::to_string(k * h) +
                         ") before its start pose is free; D is not merely slightly too large for its place");
      }
      IntersectionVolume probe(voxels_.static_grid, voxels_.dynamic_grid, problem.reference_point);
      if (probe.Iv(problem.start) == 0) {
        shrink_ = k * h;
        break;
      }
    }
    voxels_.shrink = shrink_;
    if (!colors_.empty()) {
      for (std::size_t v = 0; v < colors_.size(); ++v) {
        if (voxels_.dynamic_grid.cells[v] == kVoxelEmpty) colors_[v] = 0.0f;
      }
    }
    LogInfo("shrink: D's voxels eroded by %g (%d voxels) to free the start", shrink_,
            static_cast<int>(std::lround(shrink_ / h)));
  }
  volume_ = std::make_unique<IntersectionVolume>(voxels_.static_grid, voxels_.dynamic_grid, problem.reference_point,
                                                 NeedsLabels(mode) ? colors_ : std::vector<float>{});
  if (guarded()) {
    std::vector<float> weights = colors_;  // the colorValues alg. 12 sums: the labels', guarded
    GuardFasteners(voxels_.dynamic_grid, *volume_, problem.start, psi_, &weights, &start_voxels_, &reach_voxels_);
    volume_ = std::make_unique<IntersectionVolume>(volume_->Reweighted(weights));
    if (start_voxels_ == 0) {
      LogInfo(
          "fastener guard: D does not intersect S at the start, so no fastener is engaged: every intersection "
          "is refused (labeled-mliv-unguarded allows them up to tau)");
    } else {
      LogInfo(
          "fastener guard: %lld voxels of D intersect S at the start; %lld within psi = %.4g of them (through "
          "D); intersections elsewhere are refused",
          static_cast<long long>(start_voxels_), static_cast<long long>(reach_voxels_), psi_);
    }
  }
  triangle_part_ = TriangleParts(dynamic_mesh, &part_count_);
  bvh_ = std::make_unique<WindingBvh>(dynamic_mesh);
}

VolumeModel::~VolumeModel() = default;

int VolumeModel::GuardRigidParts(const PlanningProblem& problem, double tolerance, const FitRule& fit) {
  const auto parts = ClassifyParts(problem.robot, problem.environment, problem.start, tolerance,
                                   UnmeasuredInterference::kFastener, fit);
  if (!parts->rigid_interference.empty()) {
    LogWarn(
        "rigid guard off: %s of D already penetrates S %.4g deep at the start (the verdict's exact check will "
        "refuse any path)",
        parts->Describe(parts->rigid_interference.front(), true).c_str(),
        parts->installed_depth[parts->rigid_interference.front()]);
    return 0;
  }
  int rigid = 0;
  for (ShellRole role : parts->role) rigid += role == ShellRole::kRigid;
  if (rigid == 0) return 0;
  volume_->SetRigidGuard(std::make_shared<RigidDepthChecker>(parts, tolerance / 2, tolerance / 4));
  LogInfo("rigid guard: %d of %zu solids of D kept within %.4g of S exactly (the rest: fasteners)", rigid,
          parts->robot_shells.size(), tolerance / 2);
  return rigid;
}

double VolumeModel::Measure(const Pose& pose) { return volume_->Measure(measure(), pose); }

VolumeReport VolumeModel::Describe(const Pose& pose) {
  VolumeQuery query;
  query.record_cells = true;
  VolumeReport report;
  report.value = volume_->Measure(measure(), pose, std::numeric_limits<double>::infinity(), &query);
  report.voxels = query.voxels;
  if (query.cells.empty()) return report;
  const VoxelGridGeometry& g = voxels_.dynamic_grid.geometry;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double deformability = 0;
  for (const Eigen::Vector3i& c : query.cells) {
    sum += g.Center(c.x(), c.y(), c.z());
    if (!colors_.empty()) deformability += 1.0 - colors_[g.Index(c.x(), c.y(), c.z())];
  }
  report.centre = sum / static_cast<double>(query.cells.size());
  report.deformability = deformability / static_cast<double>(query.cells.size());
  // The part: that of the triangle nearest the component's voxel nearest its
  // centre (the centre of a bent component may lie outside it).
  Eigen::Vector3d anchor = g.Center(query.cells[0].x(), query.cells[0].y(), query.cells[0].z());
  for (const Eigen::Vector3i& c : query.cells) {
    const Eigen::Vector3d p = g.Center(c.x(), c.y(), c.z());
    if ((p - report.centre).squaredNorm() < (anchor - report.centre).squaredNorm()) anchor = p;
  }
  const WindingBvh::Closest closest = bvh_->ClosestPoint(anchor);
  if (closest.triangle >= 0) report.part = triangle_part_[closest.triangle];
  return report;
}

double VolumeModel::EstimatePsi() const { return psi_; }

}  // namespace ausbau
