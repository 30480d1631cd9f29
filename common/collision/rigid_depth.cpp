#include "collision/rigid_depth.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

#include "collision/fcl_model.h"
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
// ConvexSignedDepth; for non-convex pairs +infinity when their triangles
// intersect, else minus FCL's distance.
struct PairMeasure {
  const std::vector<Shell>* robot;
  const std::vector<Shell>* statics;
  std::vector<std::shared_ptr<FclModel>> robot_bvh, static_bvh;  // filled only for non-convex pairs' shells

  double Depth(int r, const Eigen::Isometry3d& pose, int s, double stop_gap) const {
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.convex && b.convex) return ConvexSignedDepth(a, pose, b, stop_gap);
    const fcl::Transform3d& tf = pose;  // FCL's transform is Eigen's isometry
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    fcl::collide(robot_bvh[r].get(), tf, static_bvh[s].get(), fcl::Transform3d::Identity(), request, result);
    if (result.isCollision()) return std::numeric_limits<double>::infinity();
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
    const fcl::Transform3d& tf = pose;
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    fcl::collide(robot_bvh[r].get(), tf, static_bvh[s].get(), fcl::Transform3d::Identity(), request, result);
    return result.isCollision();
  }
};

}  // namespace

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
  for (const auto& s : parts.robot_shells) measure->robot_bvh.push_back(BuildFclModel(s.vertices, s.triangles));
  for (const auto& s : parts.static_shells) measure->static_bvh.push_back(BuildFclModel(s.vertices, s.triangles));
}

}  // namespace

std::shared_ptr<const PartModel> ClassifyParts(const TriangleMesh& robot, const TriangleMesh& environment,
                                               const Pose& installed, double tolerance,
                                               UnmeasuredInterference unmeasured) {
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
  PairMeasure measure{&parts->robot_shells, &parts->static_shells, {}, {}};
  BuildFallbackModels(*parts, &measure);
  const ShellTree tree(parts->static_shells);
  const Eigen::Isometry3d pose = installed.ToIsometry();
  for (int i = 0; i < n; ++i) {
    const Shell& s = parts->robot_shells[i];
    tree.Query(pose * s.center, s.radius, [&](int j) {
      parts->installed_depth[i] = std::max(parts->installed_depth[i], measure.Depth(i, pose, j, 0.0));
    });
  }

  // 3. Fasteners: interfering shells other than the anchor, grown through
  // overlaps (touching counts) within D, never through the anchor.
  const double touch = 1e-6 * robot.Bounds().Diagonal();
  std::queue<int> open;
  int clusters = 0;
  for (int i = 0; i < n; ++i) {
    if (parts->installed_depth[i] <= tolerance || i == parts->anchor || parts->cluster[i] >= 0) continue;
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
  for (int i = 0; i < n; ++i)
    if (parts->role[i] == ShellRole::kRigid && parts->installed_depth[i] > tolerance)
      parts->rigid_interference.push_back(i);
  return parts;
}

RigidDepthChecker::RigidDepthChecker(std::shared_ptr<const PartModel> parts, double limit, double min_step)
    : parts_(std::move(parts)), limit_(limit), min_step_(min_step), impl_(std::make_unique<Impl>(*parts_)) {
  impl_->measure = PairMeasure{&parts_->robot_shells, &parts_->static_shells, {}, {}};
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
      if (valid && impl_->measure.Exceeds(r, iso, s, allowed)) valid = false;
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
      const double depth = impl_->measure.Depth(r, iso, s, margin_);
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
