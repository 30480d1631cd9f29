#include "workflow/path_profile.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "collision/rigid_depth.h"
#include "collision/scene_parts.h"
#include "core/atomic_file.h"
#include "planning/path_io.h"

namespace ausbau {

std::vector<DensePose> Densify(const PlanningProblem& problem, const std::vector<Pose>& path, double step) {
  std::vector<DensePose> out;
  if (path.empty()) return out;
  out.push_back({path.front(), 0, 0.0});
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double d = MaxDisplacement(path[i], path[i + 1], problem.robot_radius);
    const int steps = std::max(1, static_cast<int>(std::ceil(d / step)));
    for (int k = 1; k <= steps; ++k) {
      const double f = static_cast<double>(k) / steps;
      out.push_back({Interpolate(path[i], path[i + 1], f), static_cast<int>(i), f});
    }
  }
  return out;
}

TriangleMesh PathClearanceRobot(const Scene& scene, const PlanningProblem& problem, ValidityMode validity,
                                double rigid_tolerance_mm, const PartModel* classified) {
  if (validity != ValidityMode::kRigidExact) return problem.robot;
  if (classified && classified->FastenerCount() == 0) return problem.robot;  // as ClearanceRobot says then
  const double tolerance = RigidToleranceInSceneUnits(rigid_tolerance_mm, scene, nullptr);
  const auto parts = ClassifyParts(problem.robot, problem.environment, problem.start, tolerance,
                                   UnmeasuredInterference::kRigid, SceneFitRule(scene));
  return ClearanceRobot(problem, parts.get());
}

std::vector<ProfilePose> ProfileAlongPath(const PlanningProblem& problem, const ClearanceMeter& meter,
                                          const std::vector<Pose>& path) {
  std::vector<ProfilePose> out;
  if (path.empty()) return out;
  // At most ~2000 rows: the step is 1% of D's diagonal or longer.
  double total = 0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    total += MaxDisplacement(path[i], path[i + 1], problem.robot_radius);
  const double step = std::max(0.01 * problem.robot_diagonal, total / 2000.0);
  double s = 0;
  Pose previous = path.front();
  for (const DensePose& p : Densify(problem, path, step)) {
    s += problem.metric.Distance(previous, p.pose, 0.5);
    previous = p.pose;
    ProfilePose row;
    row.dense = p;
    row.s = s;
    row.clearance = meter.At(p.pose, false);
    row.clearance.segment = p.segment;
    row.clearance.fraction = p.fraction;
    out.push_back(row);
  }
  return out;
}

void WritePathProfile(const std::filesystem::path& file, const PlanningProblem& problem, const std::vector<Pose>& path,
                      VolumeModel* model, const TriangleMesh& clearance_robot, const std::string& units) {
  const ClearanceMeter meter(problem, clearance_robot);
  const std::string u = LengthUnits(units);
  std::string text = "# units: tx,ty,tz,clearance in " + u + "; qw,qx,qy,qz unitless; s normalized; volume " + u +
                     "^3; deformability 0..1; pose convention: " + kPoseConvention + "\n";
  text += "segment,fraction,s,tx,ty,tz,qw,qx,qy,qz,volume,part,deformability,clearance\n";
  char line[512];
  std::vector<ProfilePose> rows = ProfileAlongPath(problem, meter, path);
  std::vector<Pose> poses;
  for (const ProfilePose& row : rows) poses.push_back(problem.PlanningToScene(row.dense.pose));
  AlignQuaternionSigns(&poses);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ProfilePose& p = rows[i];
    const Pose& pose = poses[i];
    int n = std::snprintf(line, sizeof line, "%d,%.6f,%.8g,%.10g,%.10g,%.10g,%.9f,%.9f,%.9f,%.9f,", p.dense.segment,
                          p.dense.fraction, p.s, pose.t.x(), pose.t.y(), pose.t.z(), pose.q.w(), pose.q.x(), pose.q.y(),
                          pose.q.z());
    if (model != nullptr) {
      const VolumeReport report = model->Describe(p.dense.pose);
      n += std::snprintf(line + n, sizeof line - n, "%.8g,%d,%.4f,", report.value, report.value > 0 ? report.part : -1,
                         report.deformability);
    } else {
      n += std::snprintf(line + n, sizeof line - n, ",,,");
    }
    std::snprintf(line + n, sizeof line - n, "%.8g\n", p.clearance.clearance);
    text += line;
  }
  WriteTextFileAtomically(file, text);
}

}  // namespace ausbau
