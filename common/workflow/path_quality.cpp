#include "workflow/path_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "core/json_writer.h"
#include "planning/smoother.h"
#include "workflow/path_profile.h"

namespace ausbau {

PathQuality MeasurePathQuality(const Scene& scene, const PathArtifact& path, double rigid_tolerance_mm,
                               const PartModel* classified) {
  PathQuality quality;
  const PlanningProblem problem = MakePlanningProblem(scene);
  std::vector<Pose> poses;
  for (const Pose& pose : path.waypoints) poses.push_back(problem.SceneToPlanning(pose));
  const PathLength length = MeasurePath(problem, poses);
  quality.translation = length.translation;
  quality.rotation = length.rotation;
  quality.straight = poses.empty() ? 0 : (poses.back().t - poses.front().t).norm();
  quality.ratio = quality.straight > 0 ? quality.translation / quality.straight : std::nan("");
  quality.measured_part = path.validity == ValidityMode::kRigidExact ? "rigid shells of D" : "D";
  quality.first_rigid_segment = IsVolumeValidity(path.validity) ? std::max(0, path.inter_index) : 0;
  quality.clearance_kept = path.clearance;
  if (poses.size() < 2) return quality;
  const ClearanceMeter meter(problem,
                             PathClearanceRobot(scene, problem, path.validity, rigid_tolerance_mm, classified));
  quality.segment_clearance.assign(poses.size() - 1, std::numeric_limits<double>::infinity());
  std::optional<Pose> closest_pose;
  for (const ProfilePose& p : ProfileAlongPath(problem, meter, poses)) {
    // The first dense pose (the start) belongs to segment 0.
    const int segment = p.dense.segment;
    double& smallest = quality.segment_clearance[segment];
    smallest = std::min(smallest, p.clearance.clearance);
    // A segment's end pose is also the next one's start.
    if (p.dense.fraction == 1.0 && segment + 1 < static_cast<int>(quality.segment_clearance.size())) {
      double& next = quality.segment_clearance[segment + 1];
      next = std::min(next, p.clearance.clearance);
    }
    if (segment >= quality.first_rigid_segment && p.clearance.clearance < quality.min.clearance) {
      quality.min = p.clearance;
      quality.min_s = p.s;
      closest_pose = p.dense.pose;
    }
  }
  if (closest_pose) {  // its nearest points, measured once
    const ClearanceSample at = meter.At(*closest_pose, true);
    quality.min.on_robot = at.on_robot;
    quality.min.on_static = at.on_static;
  }
  for (std::size_t i = quality.first_rigid_segment; i < quality.segment_clearance.size(); ++i) {
    if (quality.segment_clearance[i] < quality.clearance_kept) quality.below.push_back(static_cast<int>(i));
  }
  return quality;
}

std::string PathQualityJson(const PathQuality& q) {
  JsonWriter segments(true);
  for (const double c : q.segment_clearance) segments.Append(JsonNumber(c));
  JsonWriter below(true);
  for (const int i : q.below) below.Append(std::to_string(i));
  JsonWriter min;
  if (q.min.segment >= 0) {
    min.Number("clearance", q.min.clearance)
        .Int("segment", q.min.segment)
        .Number("fraction", q.min.fraction)
        .Number("s", q.min_s)
        .Add("point_on_d", JsonVector(q.min.on_robot))
        .Add("point_on_s", JsonVector(q.min.on_static));
  }
  return JsonWriter()
      .Number("translation", q.translation)
      .Number("rotation", q.rotation)
      .Number("straight_distance", q.straight)
      .Number("translation_ratio", q.ratio)
      .String("clearance_of", q.measured_part)
      .Int("clearance_from_segment", q.first_rigid_segment)
      .Number("clearance_kept", q.clearance_kept)
      .Add("min_clearance", q.min.segment >= 0 ? min.Text() : "null")
      .Add("segment_clearance", segments.Text())
      .Add("segments_below_clearance", below.Text())
      .Text();
}

std::string PathQualityLine(const PathQuality& q, const std::string& units) {
  char line[512];
  std::snprintf(line, sizeof line,
                "translation %.4g %s, rotation %.3f rad, %.2fx the straight distance; closest to S %.4g %s (%s, "
                "segment %d)",
                q.translation, units.c_str(), q.rotation, q.ratio, q.min.clearance, units.c_str(),
                q.measured_part.c_str(), q.min.segment);
  return line;
}

std::string ClearanceWarning(const PathQuality& q, const std::string& units) {
  if (q.below.empty()) return "";
  std::string list;
  for (std::size_t i = 0; i < q.below.size(); ++i) {
    // Runs of consecutive segments as a-b.
    std::size_t j = i;
    while (j + 1 < q.below.size() && q.below[j + 1] == q.below[j] + 1) ++j;
    if (!list.empty()) list += ", ";
    list += std::to_string(q.below[i]) + (j > i ? "-" + std::to_string(q.below[j]) : "");
    i = j;
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "%s comes %.4g %s from S (segment %d, s %.4g), below the clearance of %.4g %s in %zu of %zu segments "
                "(",
                q.measured_part.c_str(), q.min.clearance, units.c_str(), q.min.segment, q.min_s, q.clearance_kept,
                units.c_str(), q.below.size(), q.segment_clearance.size() - q.first_rigid_segment);
  return line + list + "): the geometry leaves no more there";
}

}  // namespace ausbau
