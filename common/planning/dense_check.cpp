#include "planning/dense_check.h"

#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "collision/fcl_model.h"
#include "scene/scene.h"

namespace ausbau {

DenseCheckReport DenseCheckPath(const Scene& scene, const Eigen::Vector3d& reference_point,
                                const std::vector<Pose>& waypoints, double step_fraction,
                                std::chrono::steady_clock::time_point deadline) {
  DenseCheckReport report;
  const auto robot = BuildFclModel(scene.dynamic_mesh);  // mesh coordinates, not shifted
  const auto environment = BuildFclModel(scene.static_mesh);
  const double step = step_fraction * scene.dynamic_mesh.Bounds().Diagonal();
  double radius = 0;  // farthest vertex from the interpolation centre
  for (const auto& v : scene.dynamic_mesh.vertices) radius = std::max(radius, (v - reference_point).norm());

  // A scene pose (t, q) places mesh point x at R (x - o) + t. About the
  // reference point r the same pose reads R (x - r) + t + R (r - o).
  const Eigen::Vector3d r_minus_o = reference_point - scene.dynamic_origin;
  auto about_reference = [&](const Pose& p) { return Pose{p.t + p.q * r_minus_o, p.q}; };
  auto check = [&](const Pose& centred, int segment, double fraction) {
    ++report.poses_checked;
    const Eigen::Matrix3d rotation = centred.q.toRotationMatrix();
    // World transform of mesh coordinates: R x + (t_r - R r).
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.linear() = rotation;
    tf.translation() = centred.t - rotation * reference_point;
    if (scene.bounds) {
      const Eigen::Vector3d origin_world = tf * scene.dynamic_origin;
      if (!scene.bounds->Contains(origin_world)) {
        report.valid = false;
        report.reason = "leaves the bounds";
      }
    }
    if (report.valid) {
      fcl::CollisionRequestd request;
      fcl::CollisionResultd result;
      fcl::collide(robot.get(), tf, environment.get(), fcl::Transform3d::Identity(), request, result);
      if (result.isCollision()) {
        report.valid = false;
        report.reason = "in collision";
      }
    }
    if (!report.valid) {
      report.first_bad_segment = segment;
      report.first_bad_fraction = fraction;
    }
    return report.valid;
  };

  if (waypoints.empty()) {
    report.valid = false;
    report.reason = "empty path";
    return report;
  }
  if (!check(about_reference(waypoints[0]), 0, 0.0)) return report;
  for (std::size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const Pose a = about_reference(waypoints[i]), b = about_reference(waypoints[i + 1]);
    const double displacement = (b.t - a.t).norm() + radius * RotationAngle(a.q, b.q);
    // In 64 bits: a motion across bounds of 1e9 at a step of 0.1 is 1e10 steps.
    const std::int64_t steps =
        std::max<std::int64_t>(1, static_cast<std::int64_t>(std::min(std::ceil(displacement / step), 1e18)));
    for (std::int64_t k = 1; k <= steps; ++k) {
      if (report.poses_checked % 256 == 255 && deadline != std::chrono::steady_clock::time_point::max() &&
          std::chrono::steady_clock::now() >= deadline) {
        report.valid = false;
        report.stopped_by_deadline = true;
        report.first_bad_segment = static_cast<int>(i);
        report.reason = "not finished by the deadline (" + std::to_string(report.poses_checked) + " poses checked)";
        return report;
      }
      const double s = static_cast<double>(k) / static_cast<double>(steps);
      if (!check(Interpolate(a, b, s), static_cast<int>(i), s)) return report;
    }
  }
  return report;
}

}  // namespace ausbau
