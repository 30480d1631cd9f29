#include "collision/rigid_depth.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>
#include <numeric>
#include <optional>
#include <queue>

#include "collision/fcl_model.h"
#include "collision/mesh_depth.h"
#include "core/error.h"
#include "core/format.h"
#include "geometry/protrusions.h"
#include "geometry/triangle_bvh.h"

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

// What a caller of PairMeasure::Depth needs of the number.
struct DepthQuery {
  // > 0: a separated pair may stop at a gap larger than this (the value is
  // then minus that gap).
  double stop_gap = 0;
  // A depth below which the caller needs no precision.
  double settle = 0;
  // A depth above which it needs only a share (mesh_depth.h).
  double coarse_above = std::numeric_limits<double>::infinity();
  // The robot shell with its moulded fasteners (for reports).
  bool whole = false;
  // A depth beyond which the caller needs no number at all (the pose is
  // invalid): the search stops once the depth is known to exceed it, and
  // what it returns then exceeds it too, but bounds nothing.
  double decide = std::numeric_limits<double>::infinity();
  // Surfaces that meet are a collision (+infinity), not measured
  // (NewContacts::kCollide).
  bool contact_collides = false;
};

}  // namespace

// The models of the shells themselves (PartModel::shell_models; not of
// their moulded fasteners' rigid rest, which ClassifyParts finds after it
// measures). Filled only where a non-convex pair needs them
// (BuildShellModels).
struct ShellModels {
  std::vector<std::shared_ptr<FclModel>> robot_bvh, static_bvh;
  std::vector<std::shared_ptr<const DepthSurface>> robot_surface, static_surface;
  // Per convex shell: the face normals SlabGap bounds along (SlabAxes).
  std::vector<std::vector<int>> robot_slab_axes, static_slab_axes;
};

namespace {

// The pair depth of a robot shell at `pose` and a static shell: see
// ConvexSignedDepth; for non-convex pairs the surface depth where their
// surfaces meet (collision/mesh_depth.h), else minus FCL's distance. The
// shells' models are its base (BuildFallbackModels).
struct PairMeasure : ShellModels {
  const std::vector<Shell>* robot = nullptr;
  const std::vector<Shell>* statics = nullptr;
  // Robot shells with moulded fasteners: the surface that bounds the rigid
  // rest (the triangles outside the fasteners' boxes and each box's face on
  // the plate, which holds the cut), and a vertex of it; null elsewhere.
  std::vector<std::shared_ptr<FclModel>> rigid_bvh;
  std::vector<Eigen::Vector3d> rigid_vertex;
  // The same surface for SlabGap: its corners, triangles and their tree.
  struct RestSurface {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::array<int, 3>> triangles;
    TriangleBvh bvh;
  };
  std::vector<std::shared_ptr<const RestSurface>> rigid_rest;
  double resolution = 0;  // of the surface depth
  // Per robot shell, the boxes of its moulded fasteners (PartModel::masks);
  // null: none anywhere.
  const std::vector<std::shared_ptr<const DepthMask>>* masks = nullptr;
  const DepthMask* MaskOf(int r) const {
    return masks && r < static_cast<int>(masks->size()) ? (*masks)[r].get() : nullptr;
  }

  // Whether the surfaces of a non-convex pair meet: their triangles
  // intersect, or one shell holds the other (a vertex inside). For a shell
  // with moulded fasteners (unless `whole`), its rigid rest: the surface
  // that bounds it (rigid_bvh: its triangles outside the fasteners' boxes
  // and each box's face on the plate), a vertex of the rest inside s, or
  // one of s inside the shell outside the boxes. Where they do not meet,
  // they are apart by at least the distance of those surfaces.
  bool Meet(int r, const Eigen::Isometry3d& pose, int s, bool whole = false) const {
    const DepthMask* mask = whole ? nullptr : MaskOf(r);
    const fcl::Transform3d& tf = pose;  // FCL's transform is Eigen's isometry
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    fcl::collide((mask ? rigid_bvh : robot_bvh)[r].get(), tf, static_bvh[s].get(), fcl::Transform3d::Identity(),
                 request, result);
    if (result.isCollision()) return true;
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.vertices.empty() || b.vertices.empty()) return false;
    if (static_surface[s]->SignedDistance(pose * (mask ? rigid_vertex[r] : a.vertices.front())) > 0) return true;
    const Eigen::Vector3d q = pose.inverse() * b.vertices.front();
    return robot_surface[r]->SignedDistance(q) > 0 && !(mask && mask->Contains(q));
  }

  // A lower bound on the distance of a pair where one shell is convex and
  // the other a solid that is not, without FCL: each face direction of the
  // convex shell (at most kMaxSlabAxes of them, SlabAxes) bounds it by a
  // slab, and a triangle outside a slab is at least that far from it (the
  // separating-axis bound along the convex shell's face normals, per
  // triangle of the other). Only the triangles whose box meets the box
  // about the convex shell's bounding sphere grown by `reach` are looked
  // at; the others are at least `reach` away. 0 (no bound) where a near
  // triangle meets every slab, where the convex shell may lie inside the
  // other (its first corner is inside), and for any other kind of pair;
  // else min(reach, the bound) > 0, and the two solids are that far apart
  // at least. Cheap where they are near but apart (a
  // moulded panel over S's boxes, a T-key in its channel), which is most of
  // what a planner asks; where it says nothing, Meet and FCL decide.
  //
  // For a robot shell with moulded fasteners (unless `whole`), the bound is
  // the rigid rest's: the triangles of the surface that bounds it (Meet).
  // The fasteners' own triangles, which reach into S's holes, would leave
  // most pairs of a clip panel without a bound and to FCL's distance.
  double SlabGap(int r, const Eigen::Isometry3d& pose, int s, double reach, bool whole = false) const {
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.convex == b.convex) return 0;
    const Shell& convex = a.convex ? a : b;
    const DepthSurface& other = a.convex ? *static_surface[s] : *robot_surface[r];
    if (!other.solid() || convex.corners.empty()) return 0;
    const RestSurface* rest = !a.convex && !whole && MaskOf(r) != nullptr ? rigid_rest[r].get() : nullptr;
    const std::vector<Eigen::Vector3d>& vertices = rest ? rest->vertices : other.vertices();
    const std::vector<std::array<int, 3>>& triangles = rest ? rest->triangles : other.triangles();
    // The other shell's frame from the convex one's.
    const Eigen::Isometry3d other_from_convex = a.convex ? pose : pose.inverse();
    const Eigen::Isometry3d convex_from_other = other_from_convex.inverse();
    const std::vector<int>& axes = a.convex ? robot_slab_axes[r] : static_slab_axes[s];
    const std::vector<double>& lo = convex.face_low;
    const std::vector<double>& hi = convex.face_high;
    const Eigen::Vector3d centre = other_from_convex * convex.center;
    const Eigen::Vector3d half = Eigen::Vector3d::Constant(convex.radius + reach);
    double gap = reach;
    bool touches = false;
    (rest ? rest->bvh : other.bvh()).ForEachTriangleNear(centre - half, centre + half, [&](int t) {
      const auto& tri = triangles[t];
      const Eigen::Vector3d p[3] = {convex_from_other * vertices[tri[0]], convex_from_other * vertices[tri[1]],
                                    convex_from_other * vertices[tri[2]]};
      double outside = -std::numeric_limits<double>::infinity();
      for (const int k : axes) {
        const Eigen::Vector3d& normal = convex.face_normals[k];
        const double d0 = normal.dot(p[0]), d1 = normal.dot(p[1]), d2 = normal.dot(p[2]);
        const double min = std::min({d0, d1, d2}), max = std::max({d0, d1, d2});
        outside = std::max({outside, min - hi[k], lo[k] - max});
      }
      if (outside <= 0) touches = true;
      gap = std::min(gap, outside);
      return !touches;  // a touching triangle settles it: no bound
    });
    if (touches || gap <= 0) return 0;
    // (Inside the whole shell: the rest, a part of it, may hold it too.)
    if (other.SignedDistance(other_from_convex * convex.corners.front()) > 0) return 0;
    return gap;
  }

  // Two sheets (mesh_depth.h: neither bounds a volume) that meet have no
  // depth to measure: not measured (infinitely deep), as any crossing of two
  // surfaces must be.
  bool BothSheets(int r, int s) const { return !robot_surface[r]->solid() && !static_surface[s]->solid(); }

  // `mask`: the robot shell's moulded fasteners left out (or null).
  SurfaceDepth Surface(int r, const Eigen::Isometry3d& pose, int s, const SurfaceDepthOptions& options,
                       const DepthMask* mask) const {
    if (BothSheets(r, s)) {
      SurfaceDepth unmeasured;
      unmeasured.lower = unmeasured.upper = std::numeric_limits<double>::infinity();
      return unmeasured;
    }
    return MeasureSurfaceDepth(*robot_surface[r], pose, *static_surface[s], options, mask);
  }
  SurfaceDepth Surface(int r, const Eigen::Isometry3d& pose, int s, const SurfaceDepthOptions& options) const {
    return Surface(r, pose, s, options, MaskOf(r));
  }

  double Depth(int r, const Eigen::Isometry3d& pose, int s, const DepthQuery& query) const {
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.convex && b.convex) return ConvexSignedDepth(a, pose, b, query.stop_gap);
    const DepthMask* mask = query.whole ? nullptr : MaskOf(r);  // the rigid rest of a shell with moulded fasteners
    // Apart by a bound (a lower bound on the distance: the depth is minus
    // it, as for a separating axis of two convex shells). The rigid rest of
    // a shell with moulded fasteners lies inside the whole, so it is as far.
    const double apart = SlabGap(r, pose, s, query.stop_gap > 0 ? query.stop_gap : a.radius + b.radius, query.whole);
    if (apart > 0) return -apart;
    if (Meet(r, pose, s, query.whole)) {
      if (query.contact_collides) return std::numeric_limits<double>::infinity();
      SurfaceDepthOptions options;
      options.resolution = resolution;
      options.settle = query.settle;
      options.coarse_above = query.coarse_above;
      options.decide = query.decide;
      return Surface(r, pose, s, options, mask).upper;
    }
    const fcl::Transform3d& tf = pose;
    fcl::DistanceRequestd distance_request;
    fcl::DistanceResultd distance_result;
    // FCL prunes every pair of bounding volumes farther apart than the
    // distance found so far, and does not reset it: started at stop_gap, it
    // skips all that lies farther (a screw in its plate's hole, 0.03 mm
    // from it, against the other plates: those need no number).
    if (query.stop_gap > 0) distance_result.min_distance = query.stop_gap;
    fcl::distance((mask ? rigid_bvh : robot_bvh)[r].get(), tf, static_bvh[s].get(), fcl::Transform3d::Identity(),
                  distance_request, distance_result);
    return -std::max(0.0, distance_result.min_distance);
  }

  // Depth(r, pose, s) > allowed (>= 0), without the distance a separated
  // non-convex pair would cost: a plain validity question.
  // `whole`: the robot shell with its moulded fasteners.
  bool Exceeds(int r, const Eigen::Isometry3d& pose, int s, double allowed, bool contact_collides = false,
               bool whole = false) const {
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.convex && b.convex) return ConvexSignedDepth(a, pose, b, 1e-300) > allowed;
    // Any positive bound proves them apart, and any reach gives one where
    // they are (a triangle not scanned lies farther than the reach from the
    // convex shell): the least reach scans the fewest triangles. S's radius
    // as the reach scanned all of a 600 mm tube about a pin in its bore,
    // 30 ms a check.
    if (SlabGap(r, pose, s, 1e-3 * a.radius, whole) > 0) return false;
    if (!Meet(r, pose, s, whole)) return false;
    if (contact_collides) return true;
    SurfaceDepthOptions options;
    options.resolution = resolution;
    options.decide = allowed;
    return Surface(r, pose, s, options, whole ? nullptr : MaskOf(r)).upper > allowed;
  }

  // The depth of a non-convex pair that Depth() found deeper than `limit`
  // by no more than its resolution, decided: measured again only where it
  // may exceed `limit`, to a hundredth of the resolution. Returns the new
  // upper bound where that is at most `limit` (the pair does not exceed it),
  // else `depth` as it was (Depth()'s bound: a number for reports).
  double Decided(int r, const Eigen::Isometry3d& pose, int s, double limit, double depth) const {
    SurfaceDepthOptions options;
    options.resolution = resolution / 100;
    options.settle = limit;  // below it, no precision is needed
    options.decide = limit;  // above it, none either: it exceeds it
    const double decided = Surface(r, pose, s, options).upper;
    return decided <= limit ? decided : depth;
  }

  // Whether the pair may exceed `allowed` anywhere on the translation from
  // `pose` by `move` (world): false only where proved for the whole motion
  // (a convex pair by ConvexSweptDepthBound; a non-convex one apart by more
  // than the motion, or by the swept surface depth). Arguments as Exceeds.
  bool SweepMayExceed(int r, const Eigen::Isometry3d& pose, const Eigen::Vector3d& move, int s, double allowed,
                      bool contact_collides, bool whole) const {
    const Shell& a = (*robot)[r];
    const Shell& b = (*statics)[s];
    if (a.convex && b.convex) return ConvexSweptDepthBound(a, pose, move, b) > allowed;
    const double length = move.norm();
    // A lower bound on the distance above the motion's length: they never
    // meet on the way.
    if (SlabGap(r, pose, s, 2 * length + a.radius, whole) > length) return false;
    const DepthMask* mask = whole ? nullptr : MaskOf(r);
    fcl::DistanceRequestd distance_request;
    fcl::DistanceResultd distance_result;
    // Only whether they are apart by more than the motion: FCL need not look
    // farther (Depth).
    if (length > 0) distance_result.min_distance = 2 * length;
    const fcl::Transform3d& tf = pose;
    fcl::distance((mask ? rigid_bvh : robot_bvh)[r].get(), tf, static_bvh[s].get(), fcl::Transform3d::Identity(),
                  distance_request, distance_result);
    // Apart by more than the motion (and not one inside the other, which
    // would need their surfaces to cross on the way in).
    if (distance_result.min_distance > length && !Meet(r, pose, s, whole)) return false;
    if (contact_collides || BothSheets(r, s)) {
      // Any meeting is a collision (or unmeasured): proved only where the
      // surfaces never meet on the way (apart at the start, as a valid
      // start has them).
      if (Meet(r, pose, s, whole)) return true;
      const PairMeasure::RestSurface* rest = mask ? rigid_rest[r].get() : nullptr;
      return SweptSurfacesMayMeet(rest ? rest->vertices : a.vertices, rest ? rest->triangles : a.triangles, pose, move,
                                  *static_surface[s], 0.0);
    }
    SurfaceDepthOptions options;
    options.resolution = resolution;
    options.decide = allowed;
    return MeasureSweptSurfaceDepth(*robot_surface[r], pose, move, *static_surface[s], options, kMaxSweptSubTriangles,
                                    mask)
               .upper > allowed;
  }
  // The work one pair's swept question may take: beyond it the answer is
  // "not proved" (the motion is then walked pose by pose).
  static constexpr int kMaxSweptSubTriangles = 1 << 14;
};

}  // namespace

bool PartModel::InstalledContact(int robot_shell, int static_shell) const {
  return std::binary_search(installed_contacts.begin(), installed_contacts.end(),
                            std::make_pair(robot_shell, static_shell));
}

bool PartModel::Engages(int robot_shell, int static_shell) const {
  const std::vector<int>* engaged = nullptr;
  if (role[robot_shell] == ShellRole::kFastener) {
    engaged = &cluster_engages[cluster[robot_shell]];
  } else if (robot_shell < static_cast<int>(mask_engages.size())) {
    engaged = &mask_engages[robot_shell];
  }
  return engaged != nullptr && std::binary_search(engaged->begin(), engaged->end(), static_solid[static_shell]);
}

double PartModel::FitDepth(int robot_shell, int static_shell) const {
  for (const auto& fit : fits)
    if (fit.robot_shell == robot_shell && fit.static_shell == static_shell) return fit.installed_depth;
  return 0;
}

double PartModel::OverlapDepth(int robot_shell, int static_shell) const {
  for (const auto& overlap : overlaps)
    if (overlap.robot_shell == robot_shell && overlap.static_shell == static_shell) return overlap.installed_depth;
  return 0;
}

int PartModel::FastenerCount() const {
  return static_cast<int>(std::count(role.begin(), role.end(), ShellRole::kFastener) + moulded.size());
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

// The face normals of a convex shell that SlabGap bounds along: all of
// them when few (a box: 3), else kMaxSlabAxes spread over them (farthest
// first, from the first). Each slab bounds the distance on its own, so any
// subset gives a lower bound; spread ones lose little (24 about a cylinder:
// a bound within 0.2% of all of them). A cylinder's hundreds of facets
// (as1's rod at a fine tessellation: 151 axes) made the bound cost 151 dot
// products per triangle of the other shell, most of the time of a check.
constexpr int kMaxSlabAxes = 24;
std::vector<int> SlabAxes(const Shell& shell) {
  const int n = static_cast<int>(shell.face_normals.size());
  std::vector<int> axes;
  if (!shell.convex) return axes;
  if (n <= kMaxSlabAxes) {
    axes.resize(n);
    std::iota(axes.begin(), axes.end(), 0);
    return axes;
  }
  // closest[k]: how near normal k is to a chosen one (|cos|, up to sign).
  std::vector<double> closest(n, -1.0);
  for (int next = 0; static_cast<int>(axes.size()) < kMaxSlabAxes;) {
    axes.push_back(next);
    for (int k = 0; k < n; ++k)
      closest[k] = std::max(closest[k], std::abs(shell.face_normals[k].dot(shell.face_normals[next])));
    next = static_cast<int>(std::min_element(closest.begin(), closest.end()) - closest.begin());
  }
  return axes;
}

// S's shells and their models, kept for the next classification of the
// same S (the same triangles, crop box included). A stage classifies one S
// several times: ausbau-plan for its search and again for the exact check
// of the path it writes (D in another frame), ausbau-smooth and
// ausbau-verdict likewise; and S (a CAD assembly's rest, 300,000 triangles)
// is nearly all of the work: splitting it into shells and building their
// FCL trees and depth surfaces, 45% of a plan of CAx-IF s1's head.
struct StaticSide {
  TriangleMesh mesh;  // the key, compared in full
  std::vector<Shell> shells;
  std::once_flag models_built;  // the models: only where some pair is non-convex
  std::vector<std::shared_ptr<FclModel>> bvh;
  std::vector<std::shared_ptr<const DepthSurface>> surface;
  std::vector<std::vector<int>> slab_axes;
};

bool SameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  const auto same_box = [](const std::optional<Aabb>& x, const std::optional<Aabb>& y) {
    return x.has_value() == y.has_value() && (!x || (x->min == y->min && x->max == y->max));
  };
  return a.vertices.size() == b.vertices.size() && a.triangles.size() == b.triangles.size() &&
         same_box(a.cropped_to, b.cropped_to) && a.vertices == b.vertices && a.triangles == b.triangles;
}

// The StaticSide of `environment`, from the last few classified (those
// together no more than kKeptTriangles, so a stage's memory stays about
// what its largest S needs), else split now.
std::shared_ptr<StaticSide> StaticSideOf(const TriangleMesh& environment) {
  constexpr std::size_t kKeptTriangles = 2'000'000;
  static std::mutex mutex;
  static std::deque<std::shared_ptr<StaticSide>> kept;  // the most recent first
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (auto it = kept.begin(); it != kept.end(); ++it) {
      if (!SameMesh((*it)->mesh, environment)) continue;
      std::shared_ptr<StaticSide> side = *it;
      kept.erase(it);
      kept.push_front(side);
      return side;
    }
  }
  auto side = std::make_shared<StaticSide>();
  side->mesh = environment;
  side->shells = SplitIntoShells(environment);
  const std::lock_guard<std::mutex> lock(mutex);
  kept.push_front(side);
  std::size_t triangles = 0;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    triangles += kept[i]->mesh.triangles.size();
    if (i > 0 && triangles > kKeptTriangles) {
      kept.resize(i);
      break;
    }
  }
  return side;
}

// FCL models for every shell that is part of a non-convex pair: built for
// all shells of both sides as soon as either side has a non-convex shell
// (none otherwise: empty). `side`: S's, whose models are built once and
// shared (else built here).
std::shared_ptr<const ShellModels> BuildShellModels(const PartModel& parts, StaticSide* side) {
  auto models = std::make_shared<ShellModels>();
  const auto any_non_convex = [](const std::vector<Shell>& shells) {
    return std::any_of(shells.begin(), shells.end(), [](const Shell& s) { return !s.convex; });
  };
  if (!any_non_convex(parts.robot_shells) && !any_non_convex(parts.static_shells)) return models;
  for (const auto& s : parts.robot_shells) {
    models->robot_bvh.push_back(BuildFclModel(s.vertices, s.triangles));
    models->robot_surface.push_back(std::make_shared<DepthSurface>(s));
    models->robot_slab_axes.push_back(SlabAxes(s));
  }
  const auto build_static = [&parts](std::vector<std::shared_ptr<FclModel>>* bvh,
                                     std::vector<std::shared_ptr<const DepthSurface>>* surface,
                                     std::vector<std::vector<int>>* slab_axes) {
    for (const auto& s : parts.static_shells) {
      bvh->push_back(BuildFclModel(s.vertices, s.triangles));
      surface->push_back(std::make_shared<DepthSurface>(s));
      slab_axes->push_back(SlabAxes(s));
    }
  };
  if (side == nullptr) {
    build_static(&models->static_bvh, &models->static_surface, &models->static_slab_axes);
    return models;
  }
  std::call_once(side->models_built, build_static, &side->bvh, &side->surface, &side->slab_axes);
  models->static_bvh = side->bvh;
  models->static_surface = side->surface;
  models->static_slab_axes = side->slab_axes;
  return models;
}

// The models PairMeasure needs: the shells' (`models`: built once per
// PartModel) and, where a non-convex pair needs them, the rigid rest of
// each shell with moulded fasteners.
void BuildFallbackModels(const PartModel& parts, const ShellModels& models, PairMeasure* measure) {
  static_cast<ShellModels&>(*measure) = models;  // shared pointers: the models themselves are not copied
  if (models.robot_bvh.empty()) return;          // only convex pairs
  // The rigid rest of each shell with moulded fasteners (PairMeasure::rigid_bvh).
  measure->rigid_bvh.assign(parts.robot_shells.size(), nullptr);
  measure->rigid_rest.assign(parts.robot_shells.size(), nullptr);
  measure->rigid_vertex.assign(parts.robot_shells.size(), Eigen::Vector3d::Zero());
  for (std::size_t r = 0; r < parts.robot_shells.size(); ++r) {
    const DepthMask* mask = parts.Mask(static_cast<int>(r));
    if (mask == nullptr) continue;
    const Shell& shell = parts.robot_shells[r];
    std::vector<Eigen::Vector3d> vertices = shell.vertices;
    std::vector<std::array<int, 3>> triangles;
    for (std::size_t t = 0; t < shell.triangles.size(); ++t)
      if (!mask->skip_triangle[t]) triangles.push_back(shell.triangles[t]);
    if (!triangles.empty()) measure->rigid_vertex[r] = shell.vertices[triangles.front()[0]];
    for (const MouldedFastener& fastener : parts.moulded) {
      if (fastener.shell != static_cast<int>(r)) continue;
      const TurnedBox& box = fastener.box;
      const Eigen::Vector3d face = box.center - fastener.side * box.half.z() * box.axes.col(2);
      const int first = static_cast<int>(vertices.size());
      for (int corner = 0; corner < 4; ++corner)
        vertices.push_back(face + ((corner & 1) ? 1.0 : -1.0) * box.half.x() * box.axes.col(0) +
                           ((corner & 2) ? 1.0 : -1.0) * box.half.y() * box.axes.col(1));
      triangles.push_back({first, first + 1, first + 3});
      triangles.push_back({first, first + 3, first + 2});
    }
    measure->rigid_bvh[r] = BuildFclModel(vertices, triangles);
    auto rest = std::make_shared<PairMeasure::RestSurface>();
    rest->bvh = TriangleBvh(vertices, triangles);
    rest->vertices = std::move(vertices);
    rest->triangles = std::move(triangles);
    measure->rigid_rest[r] = std::move(rest);
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
  if (depth <= rule.tessellation_depth) return true;
  const Shell& a = parts.robot_shells[r];
  const Shell& b = parts.static_shells[s];
  if (depth > FitRule::kShareOfSize * std::min(a.box.Diagonal(), b.box.Diagonal())) return false;
  SurfaceDepthOptions options;
  options.resolution = parts.tolerance / 10;
  options.region_depth = parts.tolerance;
  const SurfaceDepth measured = MeasureSurfaceDepth(DepthSurface(a), pose, DepthSurface(b), options);
  fit->area = measured.region_area;
  if (fit->area < FitRule::kAreaPerDepthSquared * depth * depth) return false;
  // It must slide out (FitRule::kMaxAcrossRelease): the direction the
  // overlapping surfaces are most parallel to is the normal tensor's
  // eigenvector of the least eigenvalue, and that eigenvalue over the trace
  // is the mean squared cosine of their normals with it.
  const double trace = measured.region_normals.trace();
  if (!(trace > 0)) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(measured.region_normals);
  fit->release = eigen.eigenvectors().col(0);
  return eigen.eigenvalues()(0) <= FitRule::kMaxAcrossRelease * trace;
}

// The mask of the features switched on (`on`): their boxes, and the
// shell's triangles wholly in one of them (the plate's own faces never).
std::shared_ptr<DepthMask> FeatureMask(const Shell& shell, const PlateFeatures& plate, const std::vector<char>& on) {
  auto mask = std::make_shared<DepthMask>();
  for (std::size_t f = 0; f < plate.features.size(); ++f)
    if (on[f]) mask->boxes.push_back(plate.features[f].box);
  mask->skip_triangle.assign(shell.triangles.size(), 0);
  for (std::size_t t = 0; t < shell.triangles.size(); ++t) {
    if (plate.on_face[t]) continue;
    const auto& f = shell.triangles[t];
    mask->skip_triangle[t] =
        mask->ContainsAll({shell.vertices[f[0]], shell.vertices[f[1]], shell.vertices[f[2]]}) ? 1 : 0;
  }
  return mask;
}

// Rigid shell r clashes with S at the installed pose (its deep pairs, not
// all of them fits): is it a plate with fasteners moulded in (rigid_depth.h
// MouldedFastener)? Then its fasteners are the fewest features whose boxes,
// left out, leave the rest of the shell no deeper than the tolerance in any
// pair (but the fits of the plate itself): each feature in turn is kept
// rigid where the rest stays within the tolerance without it. A fit that
// the features hold (gone with all of them left out) is no fit then but a
// clip like the one that clashes: a snap hook 0.65 mm behind its rim looks
// like a press fit, and its box-soup twin, a solid of its own, is a
// fastener by the solid rule. Such fits leave `fits`. False (and
// parts.moulded_note says why) where the shell is no plate, where the rest
// still clashes, or where a fastener is too large (MouldedRule); `fits` is
// then as it was.
bool SplitMouldedFasteners(PartModel& parts, int r, const Eigen::Isometry3d& pose, const PairMeasure& measure,
                           const std::vector<std::pair<int, double>>& deep_pairs, std::vector<FitInterference>& fits) {
  const Shell& shell = parts.robot_shells[r];
  const PlateFeatures plate = FindPlateFeatures(shell);
  if (!plate.found) {
    parts.moulded_note = "no moulded fasteners in " + parts.Describe(r, true) + ": " + plate.reason;
    return false;
  }
  const double tolerance = parts.tolerance;
  const auto is_fit = [&](int s) {
    return std::any_of(fits.begin(), fits.end(), [&](const FitInterference& fit) { return fit.static_shell == s; });
  };
  const auto pair_exceeds = [&](int s, const DepthMask& mask) {
    SurfaceDepthOptions options;
    options.resolution = tolerance / 10;
    options.decide = tolerance;
    return measure.Surface(r, pose, s, options, &mask).upper > tolerance;
  };
  std::vector<char> on(plate.features.size(), 1);
  const auto all_features = FeatureMask(shell, plate, on);
  // The pairs the features must settle: the clashes, and the fits that the
  // features hold.
  std::vector<int> held;
  for (const auto& [s, depth] : deep_pairs) {
    if (!pair_exceeds(s, *all_features)) {
      held.push_back(s);
    } else if (!is_fit(s)) {
      parts.moulded_note = Fmt("no moulded fasteners in %s: %s, but the plate itself penetrates S",
                               parts.Describe(r, true).c_str(), plate.reason.c_str());
      return false;
    }
  }
  const auto exceeds = [&](const DepthMask& mask) {
    return std::any_of(held.begin(), held.end(), [&](int s) { return pair_exceeds(s, mask); });
  };
  for (std::size_t f = 0; f < on.size(); ++f) {
    on[f] = 0;
    if (exceeds(*FeatureMask(shell, plate, on))) on[f] = 1;
  }
  for (std::size_t f = 0; f < on.size(); ++f) {
    const Protrusion& feature = plate.features[f];
    if (on[f] && feature.volume > MouldedRule::kMaxShareOfShell * shell.volume) {
      parts.moulded_note =
          Fmt("no moulded fasteners in %s: the feature that intersects S at [%.6g, %.6g, %.6g] holds %.1f%% of its "
              "volume, more than a fastener's %.0f%%",
              parts.Describe(r, true).c_str(), feature.box.center.x(), feature.box.center.y(), feature.box.center.z(),
              100 * feature.volume / shell.volume, 100 * MouldedRule::kMaxShareOfShell);
      return false;
    }
  }
  const auto mask = FeatureMask(shell, plate, on);
  for (std::size_t f = 0; f < on.size(); ++f) {
    if (!on[f]) continue;
    MouldedFastener fastener;
    fastener.shell = r;
    fastener.box = plate.features[f].box;
    fastener.side = plate.features[f].side;
    fastener.volume = plate.features[f].volume;
    for (std::size_t t = 0; t < shell.triangles.size(); ++t) {
      const auto& tri = shell.triangles[t];
      if (mask->skip_triangle[t] && fastener.box.Contains(shell.vertices[tri[0]]) &&
          fastener.box.Contains(shell.vertices[tri[1]]) && fastener.box.Contains(shell.vertices[tri[2]]))
        ++fastener.triangles;
    }
    std::vector<char> others = on;
    others[f] = 0;
    const auto without = FeatureMask(shell, plate, others);
    // A number for reports: precision below the tolerance does not matter,
    // and above it a share of the depth is enough.
    SurfaceDepthOptions options;
    options.resolution = tolerance / 10;
    options.settle = tolerance;
    options.coarse_above = tolerance;
    for (const auto& [s, depth] : deep_pairs)
      fastener.installed_depth =
          std::max(fastener.installed_depth, measure.Surface(r, pose, s, options, without.get()).upper);
    parts.moulded.push_back(fastener);
  }
  parts.masks[r] = mask;
  std::vector<int>& engaged = parts.mask_engages[r];
  for (int s : held) engaged.push_back(parts.static_solid[s]);
  std::sort(engaged.begin(), engaged.end());
  engaged.erase(std::unique(engaged.begin(), engaged.end()), engaged.end());
  fits.erase(std::remove_if(fits.begin(), fits.end(),
                            [&](const FitInterference& fit) {
                              return std::find(held.begin(), held.end(), fit.static_shell) != held.end();
                            }),
             fits.end());
  return true;
}

// The solid of S each static shell belongs to (PartModel::static_solid):
// shells whose boxes come within the tolerance are joined where the shells
// do too (convex pairs by their exact gap, others by FCL's distance or one
// holding the other). Numbered in the order of their first shell.
std::vector<int> StaticSolids(const PartModel& parts, const PairMeasure& measure, const ShellTree& tree) {
  const std::vector<Shell>& shells = parts.static_shells;
  const int n = static_cast<int>(shells.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  const double tolerance = parts.tolerance;
  const auto touch = [&](int a, int b) {
    const Shell& sa = shells[a];
    const Shell& sb = shells[b];
    Aabb grown = sa.box;
    grown.min.array() -= tolerance;
    grown.max.array() += tolerance;
    if (grown.SeparatedFrom(sb.box)) return false;
    if (sa.convex && sb.convex) return ConvexSignedDepth(sa, Eigen::Isometry3d::Identity(), sb) >= -tolerance;
    if (measure.static_bvh.empty() || sa.vertices.empty() || sb.vertices.empty()) return false;
    fcl::DistanceRequestd request;
    fcl::DistanceResultd result;
    fcl::distance(measure.static_bvh[a].get(), fcl::Transform3d::Identity(), measure.static_bvh[b].get(),
                  fcl::Transform3d::Identity(), request, result);
    if (result.min_distance <= tolerance) return true;
    return measure.static_surface[b]->SignedDistance(sa.vertices.front()) > 0 ||
           measure.static_surface[a]->SignedDistance(sb.vertices.front()) > 0;
  };
  for (int a = 0; a < n; ++a) {
    tree.Query(shells[a].center, shells[a].radius + tolerance, [&](int b) {
      if (b <= a || find(a) == find(b) || !touch(a, b)) return;
      parent[find(b)] = find(a);
    });
  }
  std::vector<int> solid(n, -1), number(n, -1);
  int solids = 0;
  for (int a = 0; a < n; ++a) {
    const int root = find(a);
    if (number[root] < 0) number[root] = solids++;
    solid[a] = number[root];
  }
  return solid;
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
  const std::shared_ptr<StaticSide> static_side = StaticSideOf(environment);
  parts->static_shells = static_side->shells;
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
  PairMeasure measure;
  measure.robot = &parts->robot_shells;
  measure.statics = &parts->static_shells;
  measure.resolution = tolerance / 10;
  parts->shell_models = BuildShellModels(*parts, static_side.get());
  BuildFallbackModels(*parts, *parts->shell_models, &measure);
  const ShellTree tree(parts->static_shells);
  const Eigen::Isometry3d pose = installed.ToIsometry();
  std::vector<std::vector<std::pair<int, double>>> deep_pairs(n);  // (static shell, depth) deeper than the tolerance
  for (int i = 0; i < n; ++i) {
    const Shell& s = parts->robot_shells[i];
    tree.Query(pose * s.center, s.radius, [&](int j) {
      // Deeper than a fit may be (FitRule), the number is only reported.
      const double fit_limit =
          fit_rule.max_depth >= 0
              ? fit_rule.max_depth
              : std::max(fit_rule.tessellation_depth,
                         FitRule::kShareOfSize * std::min(s.box.Diagonal(), parts->static_shells[j].box.Diagonal()));
      DepthQuery query;
      query.settle = tolerance / 2;
      query.coarse_above = std::max(fit_limit, tolerance);
      double depth = measure.Depth(i, pose, j, query);
      // A non-convex pair's depth is an upper bound within the resolution
      // (a tenth of the tolerance), so one just above the tolerance may not
      // exceed it at all: decided then (the leads of a photo-interrupter in
      // their PCB holes, 0.0496 mm deep, measured 0.0546: a fastener, and
      // VALIDITY=auto gave the scene to the volume model, which found no
      // path; rigid-exact pulls it out in 0.4 s).
      if (depth > tolerance && depth <= tolerance + measure.resolution && !(s.convex && parts->static_shells[j].convex))
        depth = measure.Decided(i, pose, j, tolerance, depth);
      parts->installed_depth[i] = std::max(parts->installed_depth[i], depth);
      if (depth > 0 && depth <= tolerance) {
        FitInterference overlap;
        overlap.robot_shell = i;
        overlap.static_shell = j;
        overlap.installed_depth = depth;
        parts->overlaps.push_back(overlap);
      }
      if ((!s.convex || !parts->static_shells[j].convex) && depth >= -tolerance)
        parts->installed_contacts.emplace_back(i, j);
      if (depth > tolerance) deep_pairs[i].emplace_back(j, depth);
    });
  }
  std::sort(parts->installed_contacts.begin(), parts->installed_contacts.end());

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

  // The solids of S: its shells joined where they overlap or touch.
  parts->static_solid = StaticSolids(*parts, measure, tree);

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
    std::vector<int> engaged;
    while (!open.empty()) {
      const int k = open.front();
      open.pop();
      parts->role[k] = ShellRole::kFastener;
      for (const auto& [j, depth] : deep_pairs[k]) engaged.push_back(parts->static_solid[j]);
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
    // Fasteners bend as far as removal needs into the solids they engage:
    // their penetration there is reported, not limited (the volume modes
    // bound it by tau instead). Bounding it by the installed depth was
    // measured: it refuses rail-rotate-s11, whose clips must bend further
    // than installed to pass their rims. Any other solid of S they may
    // touch as a rigid shell does (PartModel::Engages).
    parts->cluster_limit.push_back(std::numeric_limits<double>::infinity());
    std::sort(engaged.begin(), engaged.end());
    engaged.erase(std::unique(engaged.begin(), engaged.end()), engaged.end());
    parts->cluster_engages.push_back(std::move(engaged));
    ++clusters;
  }
  // 5. A rigid shell's installed interference: fits, fasteners moulded into
  // it, or a clash.
  parts->masks.assign(n, nullptr);
  parts->mask_engages.assign(n, {});
  for (int i = 0; i < n; ++i) {
    if (parts->role[i] != ShellRole::kRigid || parts->installed_depth[i] <= tolerance) continue;
    const bool moulded = !only_fits[i] && std::isfinite(parts->installed_depth[i]) &&
                         SplitMouldedFasteners(*parts, i, pose, measure, deep_pairs[i], fits[i]);
    parts->fits.insert(parts->fits.end(), fits[i].begin(), fits[i].end());
    if (!only_fits[i] && !moulded) parts->rigid_interference.push_back(i);
  }
  return parts;
}

RigidDepthChecker::RigidDepthChecker(std::shared_ptr<const PartModel> parts, double limit, double min_step,
                                     NewContacts new_contacts)
    : parts_(std::move(parts)),
      limit_(limit),
      min_step_(min_step),
      new_contacts_(new_contacts),
      impl_(std::make_unique<Impl>(*parts_)) {
  impl_->measure = PairMeasure();
  impl_->measure.robot = &parts_->robot_shells;
  impl_->measure.statics = &parts_->static_shells;
  impl_->measure.resolution = limit_ / 10;
  impl_->measure.masks = &parts_->masks;
  BuildFallbackModels(*parts_, parts_->shell_models ? *parts_->shell_models : *BuildShellModels(*parts_, nullptr),
                      &impl_->measure);
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

RigidDepthChecker::PairRule RigidDepthChecker::Rule(int robot_shell, int static_shell) const {
  const PartModel& parts = *parts_;
  PairRule rule;
  if (parts.role[robot_shell] == ShellRole::kRigid) {
    rule.allowed = limit_ + parts.FitDepth(robot_shell, static_shell);
    // A pair installed deeper than half the limit may stay as deep as it
    // was, plus half the limit: room for the measurement's precision (a
    // tenth of the limit), and a planner's checker (limit: half the
    // tolerance) never allows more than the final check (the tolerance).
    if (robot_shell < static_cast<int>(parts.installed_depth.size()) && parts.installed_depth[robot_shell] > limit_ / 2)
      rule.allowed = std::max(rule.allowed, parts.OverlapDepth(robot_shell, static_shell) + limit_ / 2);
    rule.whole = parts.Mask(robot_shell) != nullptr && !parts.Engages(robot_shell, static_shell);
  } else if (parts.Engages(robot_shell, static_shell)) {
    rule.allowed = parts.cluster_limit[parts.cluster[robot_shell]] + limit_;
    rule.fastener = true;
  } else {
    rule.allowed = limit_;
  }
  return rule;
}

bool SharesStaticModels(const PartModel& a, const PartModel& b) {
  if (!a.shell_models || !b.shell_models) return false;
  const auto& x = a.shell_models->static_surface;
  const auto& y = b.shell_models->static_surface;
  return !x.empty() && x == y;
}

bool RigidDepthChecker::CheckValid(const Pose& pose) const {
  const Eigen::Isometry3d iso = pose.ToIsometry();
  const PartModel& parts = *parts_;
  bool valid = true;
  for (int r = 0; r < static_cast<int>(parts.robot_shells.size()) && valid; ++r) {
    const Shell& shell = parts.robot_shells[r];
    // Only pairs that can touch: those within the shell's radius.
    impl_->tree.Query(iso * shell.center, shell.radius, [&](int s) {
      if (!valid) return;
      const PairRule rule = Rule(r, s);
      if (std::isinf(rule.allowed)) return;  // a fastener in a solid it engages, unlimited
      if (impl_->measure.Exceeds(r, iso, s, rule.allowed, ContactCollides(r, s), rule.whole)) valid = false;
    });
  }
  return valid;
}

bool RigidDepthChecker::TranslationValid(const Pose& pose, const Eigen::Vector3d& move) const {
  const Eigen::Isometry3d iso = pose.ToIsometry();
  const PartModel& parts = *parts_;
  const double half = 0.5 * move.norm();
  bool proved = true;
  for (int r = 0; r < static_cast<int>(parts.robot_shells.size()) && proved; ++r) {
    const Shell& shell = parts.robot_shells[r];
    // The pairs that can touch anywhere on the way: within the ball about
    // the shell's centre half way.
    impl_->tree.Query(iso * shell.center + 0.5 * move, shell.radius + half, [&](int s) {
      if (!proved) return;
      const PairRule rule = Rule(r, s);
      if (std::isinf(rule.allowed)) return;
      if (impl_->measure.SweepMayExceed(r, iso, move, s, rule.allowed, ContactCollides(r, s), rule.whole))
        proved = false;
    });
  }
  return proved;
}

DepthReport RigidDepthChecker::MeasurePairs(const Pose& pose, bool report_fasteners) const {
  DepthReport report;
  report.slack = margin_;
  const Eigen::Isometry3d iso = pose.ToIsometry();
  const PartModel& parts = *parts_;
  for (int r = 0; r < static_cast<int>(parts.robot_shells.size()); ++r) {
    // A slack question is answered once one pair is too deep: the pose is
    // invalid, and the caller reads only the sign.
    if (!report_fasteners && report.slack < 0) break;
    const Shell& shell = parts.robot_shells[r];
    const bool rigid = parts.role[r] == ShellRole::kRigid;
    impl_->tree.Query(iso * shell.center, shell.radius + margin_, [&](int s) {
      if (!report_fasteners && report.slack < 0) return;
      const PairRule rule = Rule(r, s);
      // An unlimited fastener cannot lower the slack: measured for reports only.
      if (!report_fasteners && std::isinf(rule.allowed)) return;
      // A fit pair counts only its depth beyond the installed fit, and a
      // pair with an installed overlap only its depth beyond what it is
      // allowed above the limit (Rule): the rigid depth reported exceeds
      // the limit exactly where the slack is negative.
      const double fit = rigid ? parts.FitDepth(r, s) : 0.0;
      const double credit = rigid ? std::max(fit, rule.allowed - limit_) : 0.0;
      const double allowed = rule.allowed - credit;
      // Beyond fit + limit the pose is invalid whatever the digits: the
      // number is measured to a share of itself (still an upper bound).
      // Below half the limit, the slack is no less than half the limit.
      // Where the advancement's floor is already half the limit (the
      // planners and the smoother), a motion check needs no digits below
      // the limit either: a contact settled anywhere below it is stepped by
      // the floor, so refining its bound further (along every line where the
      // surfaces cross) buys no longer step. Reports print the number.
      DepthQuery query;
      query.stop_gap = margin_;
      query.settle = !report_fasteners && min_step_ >= limit_ / 2 ? fit + limit_ : fit + limit_ / 2;
      query.coarse_above = fit + limit_;
      // Beyond fit + allowed, a slack question needs no number: the search
      // stops once the depth is known to be there (a report measures it).
      if (!report_fasteners) query.decide = rule.allowed;
      query.whole = rule.whole;
      query.contact_collides = !report_fasteners && ContactCollides(r, s);
      const double measured = impl_->measure.Depth(r, iso, s, query);
      if (credit > 0) report.fit_depth = std::max(report.fit_depth, measured);
      // Moulded fasteners: the whole shell's reach, reported (not judged).
      if (report_fasteners && parts.Mask(r) != nullptr && !rule.whole) {
        DepthQuery whole;
        whole.stop_gap = margin_;
        whole.settle = limit_ / 2;
        whole.coarse_above = limit_;
        whole.whole = true;
        report.fastener_depth = std::max(report.fastener_depth, impl_->measure.Depth(r, iso, s, whole));
      }
      const double depth = measured - credit;
      report.slack = std::min(report.slack, allowed - depth);
      if (rule.fastener) {
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
