#include "planning/reach_crop.h"

#include <cmath>

#include "geometry/triangle_box.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

Aabb Grown(Aabb box, double margin) {
  box.min.array() -= margin;
  box.max.array() += margin;
  return box;
}

bool Overlap(const Aabb& a, const Aabb& b) { return !a.SeparatedFrom(b); }

bool ContainsBox(const Aabb& outer, const Aabb& inner) {
  return (inner.min.array() >= outer.min.array()).all() && (inner.max.array() <= outer.max.array()).all();
}

}  // namespace

Aabb InstalledBox(const Scene& scene) {
  Aabb box;
  for (const auto& v : scene.dynamic_mesh.vertices) box.Extend(scene.start.Apply(v - scene.dynamic_origin));
  return box;
}

std::optional<ReachCrop> ChooseReachCrop(const Scene& scene, int level) {
  if (level < 0 || scene.goal || scene.goal_condition || scene.bounds) return std::nullopt;
  const std::int64_t full = static_cast<std::int64_t>(scene.static_mesh.triangles.size());
  if (full < kCropMinTriangles) return std::nullopt;
  const Aabb installed = InstalledBox(scene);
  const double diagonal = installed.Diagonal();
  if (!(diagonal > 0) || !std::isfinite(diagonal)) return std::nullopt;
  ReachCrop crop;
  crop.level = level;
  crop.box = Grown(installed, kCropMargin * diagonal * std::ldexp(1.0, level));
  crop.clearance = kCropClearance * diagonal;
  if (ContainsBox(crop.box, scene.static_mesh.Bounds())) return std::nullopt;
  crop.full_triangles = full;
  crop.environment = CropMesh(scene.static_mesh, Grown(crop.box, crop.clearance), &crop.triangle_boxes);
  crop.kept_triangles = static_cast<std::int64_t>(crop.environment.triangles.size());
  // Level 0 decides whether the scene is cropped at all: only when the
  // region is much smaller than S.
  if (level == 0 && crop.kept_triangles * 2 > full) return std::nullopt;
  if (level > 0 && !ChooseReachCrop(scene, 0)) return std::nullopt;
  return crop;
}

bool ReachCrop::InGoal(const Aabb& robot_box) const {
  const Aabb grown = Grown(robot_box, clearance);
  const Eigen::Vector3d centre = grown.Center(), half = 0.5 * grown.Size();
  for (std::size_t i = 0; i < triangle_boxes.size(); ++i) {
    if (!Overlap(triangle_boxes[i], grown)) continue;
    const auto& t = environment.triangles[i];
    if (TriangleOverlapsBox(centre, half, environment.vertices[t[0]], environment.vertices[t[1]],
                            environment.vertices[t[2]], SatRounding::kPerAxisHalfExtent)) {
      return false;
    }
  }
  return true;
}

double ReachCrop::BallSlack(const Eigen::Vector3d& centre, double radius) const {
  const Eigen::Vector3d low = centre.array() - radius - box.min.array();
  const Eigen::Vector3d high = box.max.array() - (centre.array() + radius);
  return std::min(low.minCoeff(), high.minCoeff());
}

}  // namespace ausbau
