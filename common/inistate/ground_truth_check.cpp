#include "inistate/ground_truth_check.h"

#include <cmath>
#include <limits>

#include "collision/fcl_checker.h"
#include "inistate/intersection_volume.h"
#include "scene/scene.h"

namespace ausbau {

GroundTruthCheck CheckPathAgainstGroundTruth(const Scene& scene, const ClipGroundTruth& truth,
                                             const SceneVoxels& voxels, const Eigen::Vector3d& reference_point,
                                             const std::vector<Pose>& waypoints, double step_fraction,
                                             double tolerance_voxels) {
  GroundTruthCheck out;
  if (waypoints.empty()) {
    out.reason = "empty path";
    return out;
  }
  // Ground-truth colours: clip vertices deformable (0), the rest rigid (1).
  std::vector<double> deformability(scene.dynamic_mesh.vertices.size(), 0.0);
  for (const ClipScenePart& part : truth.parts) {
    if (!part.deformable) continue;
    for (const IndexRange& range : part.vertices) {
      for (std::int64_t v = range.begin; v < range.end && v < static_cast<std::int64_t>(deformability.size()); ++v) {
        deformability[v] = 1.0;
      }
    }
  }
  const std::vector<float> colors = ColorValues(voxels.dynamic_grid, scene.dynamic_mesh, deformability);
  // Scene-convention poses: x_world = R (x - dynamic_origin) + t, so the
  // volume's reference point is the dynamic origin; interpolation is about
  // reference_point as the planner's.
  IntersectionVolume volume(voxels.static_grid, voxels.dynamic_grid, scene.dynamic_origin, colors);
  const Aabb box = scene.dynamic_mesh.Bounds();
  const double diagonal = (box.max - box.min).norm();
  double radius = 0;
  for (const Eigen::Vector3d& v : scene.dynamic_mesh.vertices) radius = std::max(radius, (v - reference_point).norm());
  const double step = step_fraction * diagonal;
  // Interpolate about the reference point: convert to poses of it and back.
  auto to_ref = [&](const Pose& p) {
    Pose r = p;
    r.t = p.t + p.q * (reference_point - scene.dynamic_origin);
    return r;
  };
  auto from_ref = [&](const Pose& r) {
    Pose p = r;
    p.t = r.t - r.q * (reference_point - scene.dynamic_origin);
    return p;
  };
  out.start_rigid_volume = volume.LabeledMliv(waypoints.front());
  out.max_rigid_volume = out.start_rigid_volume;
  Pose worst_pose = waypoints.front();
  // D's rigid triangles for the exact test, about the dynamic origin (so
  // scene-convention poses apply as they are).
  TriangleMesh rigid;
  rigid.vertices = scene.dynamic_mesh.vertices;
  for (Eigen::Vector3d& v : rigid.vertices) v -= scene.dynamic_origin;
  const std::vector<bool> clip_triangle = truth.ClipTriangleMask();
  for (std::size_t t = 0; t < scene.dynamic_mesh.triangles.size(); ++t) {
    if (t >= clip_triangle.size() || !clip_triangle[t]) rigid.triangles.push_back(scene.dynamic_mesh.triangles[t]);
  }
  const FclCollisionChecker exact(rigid, scene.static_mesh);
  auto check = [&](const Pose& pose, int segment) {
    ++out.poses_checked;
    if (!exact.InCollision(pose)) return;  // no rigid triangle touches S
    const double v = volume.LabeledMliv(pose);
    if (v > out.max_rigid_volume) {
      out.max_rigid_volume = v;
      out.worst_segment = segment;
      worst_pose = pose;
    }
  };
  for (std::size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const Pose a = to_ref(waypoints[i]), b = to_ref(waypoints[i + 1]);
    const int steps = std::max(1, static_cast<int>(std::ceil(MaxDisplacement(a, b, radius) / step)));
    for (int s = 1; s <= steps; ++s) check(from_ref(Interpolate(a, b, static_cast<double>(s) / steps)), static_cast<int>(i));
  }
  const double tolerance = tolerance_voxels * volume.voxel_volume();
  out.rigid_ok = out.max_rigid_volume <= out.start_rigid_volume + tolerance;
  // Disassembled: D's box at the last pose separated from S's.
  const Pose& last = waypoints.back();
  Aabb moved;
  for (const Eigen::Vector3d& v : scene.dynamic_mesh.vertices) moved.Extend(last.q * (v - scene.dynamic_origin) + last.t);
  out.ends_disassembled = moved.SeparatedFrom(scene.static_mesh.Bounds());
  out.correct = out.rigid_ok && out.ends_disassembled;
  if (out.worst_segment >= 0) {
    // The part of the vertex nearest the worst component's first voxel.
    VolumeQuery query;
    query.record_cells = true;
    volume.LabeledMliv(worst_pose, std::numeric_limits<double>::infinity(), &query);
    if (!query.cells.empty()) {
      const Eigen::Vector3d p =
          voxels.dynamic_grid.geometry.Center(query.cells[0].x(), query.cells[0].y(), query.cells[0].z());
      std::int64_t nearest = 0;
      for (std::size_t v = 1; v < scene.dynamic_mesh.vertices.size(); ++v) {
        if ((scene.dynamic_mesh.vertices[v] - p).squaredNorm() <
            (scene.dynamic_mesh.vertices[nearest] - p).squaredNorm()) {
          nearest = static_cast<std::int64_t>(v);
        }
      }
      for (const ClipScenePart& part : truth.parts) {
        for (const IndexRange& range : part.vertices) {
          if (range.Contains(nearest)) out.worst_part = part.name;
        }
      }
    }
  }
  if (!out.rigid_ok) {
    char text[200];
    std::snprintf(text, sizeof text, "rigid parts penetrate S: %.4g > %.4g (start) + %.4g on segment %d (%s)",
                  out.max_rigid_volume, out.start_rigid_volume, tolerance, out.worst_segment,
                  out.worst_part.c_str());
    out.reason = text;
  } else if (!out.ends_disassembled) {
    out.reason = "does not end in the disassembly region";
  }
  return out;
}

}  // namespace ausbau
