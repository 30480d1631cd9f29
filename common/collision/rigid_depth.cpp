#include "collision/rigid_depth.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

#include "collision/fcl_model.h"
#include "collision/mesh_depth.h"
#include "core/format.h"

namespace ausbau {
namespace {

// A static bounding-box tree over S's shells: which shells come within a
// distance of a sphere.
class ShellTree {
 public:
  explicit ShellTree(const std::vector<Shell>& shells) : shells_(&shells) {
    order_.resize(shells.size());
    std::iota(order_.begin(), order_.end(), 0);
    if (!shells.empty()) Build(0, static_cast<int>(shells.size()));
  }
  template <typename Visit>
  void Query(const Eigen::Vector3d& center, double reach, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::vector<int> stack = {0};
    while (!stack.empty()) {
      const Node& node = nodes_[stack.back()];
      stack.pop_back();
      const Eigen::Vector3d excess = (node.box.min - center).cwiseMax(center - node.box.max).cwiseMax(0.0);
      if (excess.squaredNorm() > reach * reach) continue;
      if (node.left < 0) {
        for (int i = node.begin; i < node.end; ++i) {
          const Aabb& box = (*shells_)[order_[i]].box;
          const Eigen::Vector3d e = (box.min - center).cwiseMax(center - box.max).cwiseMax(0.0);
          if (e.squaredNorm() <= reach * reach) visit(order_[i]);
        }
      } else {
        stack.push_back(node.left);
        stack.push_back(node.right);
      }
    }
  }

 private:
  struct Node {
    Aabb box;
    int begin = 0, end = 0, left = -1, right = -1;
  };
  int Build(int begin, int end) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Aabb box;
    for (int i = begin; i < end; ++i) box.Extend((*shells_)[order_[i]].box);
    nodes_[index].box = box;
    nodes_[index].begin = begin;
    nodes_[index].end = end;
    if (end - begin <= 4) return index;
    int axis = 0;
    box.Size().maxCoeff(&axis);
    const int mid = (begin + end) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](int a, int b) { return (*shells_)[a].center[axis] < (*shells_)[b].center[axis]; });
    const int left = Build(begin, mid);
    const int right = Build(mid, end);
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
  }
  const std::vector<Shell>* shells_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

// The pair depth of a robot shell at `pose` and a static shell: see
// ConvexSignedDepth; for non-convex pairs the surface depth where their
// surfaces meet (collision/mesh_depth.h), else minus FCL's distance.
struct PairMeasure {
  const std::vector<Shell>* robot;
  const std::vector<Shell>* statics;
  // Filled only where a non-convex pair needs them (BuildFallbackModels).
  std::vector<std::shared_ptr<FclModel>> robot_bvh, static_bvh;
  std::vector<std::shared_ptr<const DepthSurface>> robot_surface, static_surface;
  double resolution = 0;  // of the surface depth

  // Whether the surfaces of a non-convex pair meet: their triangles
  // intersect, or one shell holds the other (a vertex inside).
  bool Meet(int r, const Eigen::Isometry3d& pose, int s) const {
    const fcl::Transform3d& tf = pose;  // FCL's transform is Eigen's isometry
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    fcl::collide(robot_bvh[r].get(), tf, static_bvh[s].get(), fcl::Transform3d::Identity(), request, result);
    if (result.isCollision()) return true;
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.vertices.empty() || b.vertices.empty()) return false;
    return static_surface[s]->SignedDistance(pose * a.vertices.front()) > 0 ||
           robot_surface[r]->SignedDistance(pose.inverse() * b.vertices.front()) > 0;
  }

  // Two sheets (mesh_depth.h: neither bounds a volume) that meet have no
  // depth to measure: not measured (infinitely deep), as any crossing of two
  // surfaces must be.
  bool BothSheets(int r, int s) const { return !robot_surface[r]->solid() && !static_surface[s]->solid(); }

  SurfaceDepth Surface(int r, const Eigen::Isometry3d& pose, int s, const SurfaceDepthOptions& options) const {
    if (BothSheets(r, s)) {
      SurfaceDepth unmeasured;
      unmeasured.lower = unmeasured.upper = std::numeric_limits<double>::infinity();
      return unmeasured;
    }
    return MeasureSurfaceDepth(*robot_surface[r], pose, *static_surface[s], options);
  }

  // `settle`: a depth below which the caller needs no precision;
  // `coarse_above`: one above which it needs only a share (mesh_depth.h).
  double Depth(int r, const Eigen::Isometry3d& pose, int s, double stop_gap, double settle,
               double coarse_above = std::numeric_limits<double>::infinity()) const {
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.convex && b.convex) return ConvexSignedDepth(a, pose, b, stop_gap);
    if (Meet(r, pose, s)) {
      SurfaceDepthOptions options;
      options.resolution = resolution;
      options.settle = settle;
      options.coarse_above = coarse_above;
      return Surface(r, pose, s, options).upper;
    }
    const fcl::Transform3d& tf = pose;
    fcl::DistanceRequestd distance_request;
    fcl::DistanceResultd distance_result;
    fcl::distance(robot_bvh[r].get(), tf, static_bvh[s].get(), fcl::Transform3d::Identity(), distance_request,
                  distance_result);
    return -std::max(0.0, distance_result.min_distance);
  }

  // Depth(r, pose, s) > allowed (>= 0), without the distance a separated
  // non-convex pair would cost: a plain validity question.
  bool Exceeds(int r, const Eigen::Isometry3d& pose, int s, double allowed) const {
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.convex && b.convex) return ConvexSignedDepth(a, pose, b, 1e-300) > allowed;
    if (!Meet(r, pose, s)) return false;
    SurfaceDepthOptions options;
    options.resolution = resolution;
    options.decide = allowed;
    return Surface(r, pose, s, options).upper > allowed;
  }
};

}  // namespace

double PartModel::FitDepth(int robot_shell, int static_shell) const {
  for (const auto& fit : fits)
    if (fit.robot_shell == robot_shell && fit.static_shell == static_shell) return fit.installed_depth;
  return 0;
}

int PartModel::FastenerCount() const {
  return static_cast<int>(std::count(role.begin(), role.end(), ShellRole::kFastener));
}

std::string PartModel::Describe(int shell, bool robot) const {
  const auto& shells = robot ? robot_shells : static_shells;
  if (shell < 0 || shell >= static_cast<int>(shells.size())) return "none";
  const Shell& s = shells[shell];
  return Fmt("shell %d (%s, %zu triangles, centre [%.6g, %.6g, %.6g], size %.3g x %.3g x %.3g)", shell,
             s.convex ? "convex" : (s.closed ? "non-convex" : "open"), s.triangles.size(), s.center.x(), s.center.y(),
             s.center.z(), s.box.Size().x(), s.box.Size().y(), s.box.Size().z());
}

struct RigidDepthChecker::Impl {
  ShellTree tree;
  PairMeasure measure;
  explicit Impl(const PartModel& parts) : tree(parts.static_shells) {}
};

namespace {

// FCL models for every shell that is part of a non-convex pair: built for
// all shells of both sides as soon as either side has a non-convex shell.
void BuildFallbackModels(const PartModel& parts, PairMeasure* measure) {
  const auto any_non_convex = [](const std::vector<Shell>& shells) {
    return std::any_of(shells.begin(), shells.end(), [](const Shell& s) { return !s.convex; });
  };
  if (!any_non_convex(parts.robot_shells) && !any_non_convex(parts.static_shells)) return;
  for (const auto& s : parts.robot_shells) {
    measure->robot_bvh.push_back(BuildFclModel(s.vertices, s.triangles));
    measure->robot_surface.push_back(std::make_shared<DepthSurface>(s));
  }
  for (const auto& s : parts.static_shells) {
    measure->static_bvh.push_back(BuildFclModel(s.vertices, s.triangles));
    measure->static_surface.push_back(std::make_shared<DepthSurface>(s));
  }
}

// Whether the installed interference of rigid shell r with static shell s,
// `depth` deep, is a fit interference (FitRule in rigid_depth.h).
bool IsFit(const PartModel& parts, int r, int s, double depth, const Eigen::Isometry3d& pose, const FitRule& rule,
           FitInterference* fit) {
  fit->robot_shell = r;
  fit->static_shell = s;
  fit->installed_depth = depth;
  if (!std::isfinite(depth)) return false;
  if (rule.max_depth >= 0) return depth <= rule.max_depth;
  const Shell& a = parts.robot_shells[r];
  const Shell& b = parts.static_shells[s];
  if (depth > FitRule::kShareOfSize * std::min(a.box.Diagonal(), b.box.Diagonal())) return false;
  SurfaceDepthOptions options;
  options.resolution = parts.tolerance / 10;
  options.region_depth = parts.tolerance;
  fit->area = MeasureSurfaceDepth(DepthSurface(a), pose, DepthSurface(b), options).region_area;
  return fit->area >= FitRule::kAreaPerDepthSquared * depth * depth;
}

}  // namespace

std::shared_ptr<const PartModel> ClassifyParts(const TriangleMesh& robot, const TriangleMesh& environment,
                                               const Pose& installed, double tolerance,
                                               UnmeasuredInterference unmeasured, const FitRule& fit_rule) {
  auto parts = std::make_shared<PartModel>();
  parts->tolerance = tolerance;
  // D is often given about its own centre (the planners' frame) while its
  // file stored it where it is installed, metres from the origin: the
  // rounding of those coordinates is what the tolerances must allow for.
  double installed_magnitude = 0;
  for (const auto& v : robot.vertices)
    installed_magnitude = std::max(installed_magnitude, installed.Apply(v).cwiseAbs().maxCoeff());
  parts->robot_shells = SplitIntoShells(robot, installed_magnitude);
  parts->static_shells = SplitIntoShells(environment);
  const int n = static_cast<int>(parts->robot_shells.size());
  parts->role.assign(n, ShellRole::kRigid);
  parts->cluster.assign(n, -1);
  parts->installed_depth.assign(n, -std::numeric_limits<double>::infinity());

  // 1. The anchor: the largest shell by volume (by box volume when none is
  // closed).
  double best = -1;
  for (int i = 0; i < n; ++i) {
    const Shell& s = parts->robot_shells[i];
    const double size = s.volume > 0 ? s.volume : s.box.Size().prod();
    if (size > best) best = size, parts->anchor = i;
  }

  // 2. Installed penetration of every shell of D.
  PairMeasure measure{&parts->robot_shells, &parts->static_shells};
  measure.resolution = tolerance / 10;
  BuildFallbackModels(*parts, &measure);
  const ShellTree tree(parts->static_shells);
  const Eigen::Isometry3d pose = installed.ToIsometry();
  std::vector<std::vector<std::pair<int, double>>> deep_pairs(n);  // (static shell, depth) deeper than the tolerance
  for (int i = 0; i < n; ++i) {
    const Shell& s = parts->robot_shells[i];
    tree.Query(pose * s.center, s.radius, [&](int j) {
      // Deeper than a fit may be (FitRule), the number is only reported.
      const double fit_limit = fit_rule.max_depth >= 0 ? fit_rule.max_depth
                                                       : FitRule::kShareOfSize * std::min(s.box.Diagonal(),
                                                                                          parts->static_shells[j].box.Diagonal());
      const double depth = measure.Depth(i, pose, j, 0.0, tolerance / 2, std::max(fit_limit, tolerance));
      parts->installed_depth[i] = std::max(parts->installed_depth[i], depth);
      if (depth > tolerance) deep_pairs[i].emplace_back(j, depth);
    });
  }

  // 3. Fit interferences (FitRule): the anchor's deep pairs, and those of
  // any shell in a pair with a non-convex shell (a CAD part against a CAD
  // part: a press fit or a tessellation overlap, where a box soup's clip
  // would be a convex box). A shell all of whose deep pairs are fits is
  // rigid: not a fastener.
  std::vector<std::vector<FitInterference>> fits(n);
  std::vector<bool> only_fits(n, false);
  for (int i = 0; i < n; ++i) {
    if (deep_pairs[i].empty()) continue;
    only_fits[i] = true;
    for (const auto& [j, depth] : deep_pairs[i]) {
      const bool cad_pair = !parts->robot_shells[i].convex || !parts->static_shells[j].convex;
      if (cad_pair && i != parts->anchor &&
          (parts->non_convex_interference.empty() || parts->non_convex_interference.back() != i))
        parts->non_convex_interference.push_back(i);
      // In the volume modes (unmeasured = kFastener) such a shell is a
      // fastener, bounded by the volume model, as before depths were measured.
      const bool may_fit = i == parts->anchor || (cad_pair && unmeasured == UnmeasuredInterference::kRigid);
      FitInterference fit;
      if (may_fit && IsFit(*parts, i, j, depth, pose, fit_rule, &fit)) {
        fits[i].push_back(fit);
      } else {
        only_fits[i] = false;
      }
    }
  }

  // 4. Fasteners: interfering shells other than the anchor, grown through
  // overlaps (touching counts) within D, never through the anchor.
  const double touch = 1e-6 * robot.Bounds().Diagonal();
  std::queue<int> open;
  int clusters = 0;
  for (int i = 0; i < n; ++i) {
    if (parts->installed_depth[i] <= tolerance || i == parts->anchor || parts->cluster[i] >= 0) continue;
    if (only_fits[i]) continue;
    // Not measured (infinite: a non-convex pair that intersects): rigid, and
    // its interference reported, unless a volume model bounds it.
    if (std::isinf(parts->installed_depth[i]) && unmeasured == UnmeasuredInterference::kRigid) continue;
    parts->cluster[i] = clusters;
    open.push(i);
    while (!open.empty()) {
      const int k = open.front();
      open.pop();
      parts->role[k] = ShellRole::kFastener;
      for (int j = 0; j < n; ++j) {
        if (j == parts->anchor || parts->cluster[j] >= 0 || !parts->robot_shells[j].convex) continue;
        const Shell& a = parts->robot_shells[k];
        const Shell& b = parts->robot_shells[j];
        if (a.box.SeparatedFrom(b.box)) continue;
        if (ConvexSignedDepth(a, Eigen::Isometry3d::Identity(), b) >= -touch) {
          parts->cluster[j] = clusters;
          open.push(j);
        }
      }
    }
    // Fasteners bend as far as removal needs: their penetration is reported,
    // not limited (the volume modes bound it by tau instead). Bounding it by
    // the installed depth was measured: it refuses rail-rotate-s11, whose
    // clips must bend further than installed to pass their rims.
    parts->cluster_limit.push_back(std::numeric_limits<double>::infinity());
    ++clusters;
  }
  // 5. A rigid shell's installed interference: fits, or a clash.
  for (int i = 0; i < n; ++i) {
    if (parts->role[i] != ShellRole::kRigid || parts->installed_depth[i] <= tolerance) continue;
    parts->fits.insert(parts->fits.end(), fits[i].begin(), fits[i].end());
    if (!only_fits[i]) parts->rigid_interference.push_back(i);
  }
  return parts;
}

RigidDepthChecker::RigidDepthChecker(std::shared_ptr<const PartModel> parts, double limit, double min_step)
    : parts_(std::move(parts)), limit_(limit), min_step_(min_step), impl_(std::make_unique<Impl>(*parts_)) {
  impl_->measure = PairMeasure{&parts_->robot_shells, &parts_->static_shells};
  impl_->measure.resolution = limit_ / 10;
  BuildFallbackModels(*parts_, &impl_->measure);
  // Pairs farther apart than this are not measured; their slack is at least
  // this. A few percent of D's size keeps the pair count small near S and
  // the steps long away from it.
  Aabb box;
  for (const auto& s : parts_->robot_shells) box.Extend(s.box);
  margin_ = std::max(0.02 * box.Diagonal(), 4 * (limit_ + min_step_));
}

RigidDepthChecker::~RigidDepthChecker() = default;

DepthReport RigidDepthChecker::Measure(const Pose& pose) const { return MeasurePairs(pose, true); }

double RigidDepthChecker::Slack(const Pose& pose) const { return MeasurePairs(pose, false).slack; }

bool RigidDepthChecker::CheckValid(const Pose& pose) const {
  const Eigen::Isometry3d iso = pose.ToIsometry();
  const PartModel& parts = *parts_;
  bool valid = true;
  for (int r = 0; r < static_cast<int>(parts.robot_shells.size()) && valid; ++r) {
    const bool rigid = parts.role[r] == ShellRole::kRigid;
    const double allowed = rigid ? limit_ : parts.cluster_limit[parts.cluster[r]] + limit_;
    if (std::isinf(allowed)) continue;
    const Shell& shell = parts.robot_shells[r];
    // Only pairs that can touch: those within the shell's radius.
    impl_->tree.Query(iso * shell.center, shell.radius, [&](int s) {
      if (valid && impl_->measure.Exceeds(r, iso, s, allowed + (rigid ? parts.FitDepth(r, s) : 0.0))) valid = false;
    });
  }
  return valid;
}

DepthReport RigidDepthChecker::MeasurePairs(const Pose& pose, bool report_fasteners) const {
  DepthReport report;
  report.slack = margin_;
  const Eigen::Isometry3d iso = pose.ToIsometry();
  const PartModel& parts = *parts_;
  for (int r = 0; r < static_cast<int>(parts.robot_shells.size()); ++r) {
    const Shell& shell = parts.robot_shells[r];
    const bool rigid = parts.role[r] == ShellRole::kRigid;
    const double allowed = rigid ? limit_ : parts.cluster_limit[parts.cluster[r]] + limit_;
    // An unlimited fastener cannot lower the slack: measured for reports only.
    if (!rigid && !report_fasteners && std::isinf(allowed)) continue;
    impl_->tree.Query(iso * shell.center, shell.radius + margin_, [&](int s) {
      // A fit pair counts only its depth beyond the installed fit. Below
      // half the limit, the slack is no less than the advancement's floor.
      const double fit = rigid ? parts.FitDepth(r, s) : 0.0;
      // Beyond fit + limit the pose is invalid whatever the digits: the
      // number is measured to a share of itself (still an upper bound).
      const double measured = impl_->measure.Depth(r, iso, s, margin_, fit + limit_ / 2, fit + limit_);
      if (fit > 0) report.fit_depth = std::max(report.fit_depth, measured);
      const double depth = measured - fit;
      report.slack = std::min(report.slack, allowed - depth);
      if (!rigid) {
        report.fastener_depth = std::max(report.fastener_depth, depth);
      } else if (depth > report.rigid_depth) {
        report.rigid_depth = depth;
        report.rigid_shell = r;
        report.rigid_static_shell = s;
      }
    });
  }
  return report;
}

}  // namespace ausbau
