#include "workflow/path_profile.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "collision/fcl_checker.h"
#include "core/atomic_file.h"

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

void WritePathProfile(const std::filesystem::path& file, const PlanningProblem& problem, const std::vector<Pose>& path,
                      VolumeModel* model) {
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  // At most ~2000 rows: the step is 1% of D's diagonal or longer.
  double total = 0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    total += MaxDisplacement(path[i], path[i + 1], problem.robot_radius);
  const double step = std::max(0.01 * problem.robot_diagonal, total / 2000.0);
  std::string text = "segment,fraction,s,volume,part,deformability,clearance\n";
  double s = 0;
  Pose previous = path.front();
  char line[256];
  for (const DensePose& p : Densify(problem, path, step)) {
    s += problem.metric.Distance(previous, p.pose, 0.5);
    previous = p.pose;
    VolumeReport report;
    if (model != nullptr) report = model->Describe(p.pose);
    const double clearance = fcl.InCollision(p.pose) ? 0.0 : fcl.Distance(p.pose);
    if (model != nullptr) {
      std::snprintf(line, sizeof line, "%d,%.6f,%.8g,%.8g,%d,%.4f,%.8g\n", p.segment, p.fraction, s, report.value,
                    report.value > 0 ? report.part : -1, report.deformability, clearance);
    } else {
      std::snprintf(line, sizeof line, "%d,%.6f,%.8g,,,,%.8g\n", p.segment, p.fraction, s, clearance);
    }
    text += line;
  }
  WriteTextFileAtomically(file, text);
}

}  // namespace ausbau
