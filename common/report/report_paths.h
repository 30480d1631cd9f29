// The paths a report shows: loaded from their artifacts, timed for the
// animation, and measured along the way (clearance, rigid and fastener
// penetration, the nearest or contacting parts of D and S).
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "collision/fcl_checker.h"
#include "collision/rigid_depth.h"
#include "core/log.h"
#include "geometry/mesh.h"
#include "planning/path_io.h"
#include "planning/state_space.h"
#include "report/report_parts.h"
#include "scene/scene.h"

namespace ausbau::report_internal {

// What the report measures at one pose (scene convention).
struct PoseMeasure {
  double clearance = 0;  // FCL distance between D and S (0 in contact)
  // Rigid shells of D into S (collision/rigid_depth.h): > 0 penetration
  // depth, <= 0 a gap, +inf where an unmeasured (non-convex) pair intersects;
  // NaN where no rigid model is used.
  double rigid_depth = std::numeric_limits<double>::quiet_NaN();
  double fastener_depth = std::numeric_limits<double>::quiet_NaN();  // clips into S
  int robot_triangle = -1, static_triangle = -1;                     // nearest (or contacting) pair
  int rigid_shell = -1, static_shell = -1;                           // deepest rigid pair, where it penetrates
};

struct PathEntry {
  std::string key;  // "planned" / "smoothed"
  std::filesystem::path file;
  PathArtifact artifact;
  std::string producer;
  std::optional<double> length_translation, length_rotation;
  std::vector<double> times;  // animation time of each waypoint, 0 .. 1
  std::vector<PoseMeasure> at_waypoints;
  std::vector<double> sample_times;  // dense samples, evenly in animation time
  std::vector<PoseMeasure> at_samples;
  std::string csv_text;  // the path as CSV (x,y,z,qw,qx,qy,qz), for the download
  std::string csv_name;
};

PathEntry LoadPath(const std::string& key, const std::filesystem::path& file);

// The animation runs at constant "speed": each segment takes time in
// proportion to how far the points of D move at most (translation of the
// reference point plus radius x rotation angle).
std::vector<double> AnimationTimes(const PathArtifact& path, const TriangleMesh& robot_mesh);

// The scene-convention pose at animation time u, interpolated as
// schemas/path.md says: linear in the reference point's position, slerp in q.
Pose PoseAtTime(const PathArtifact& path, const std::vector<double>& times, double u);

// The measurements at a pose. `rigid` may be null (no rigid model).
class PoseMeter {
 public:
  PoseMeter(const PlanningProblem& problem, std::shared_ptr<const PartModel> parts, double tolerance);
  PoseMeasure Measure(const Pose& scene_pose) const;
  bool has_rigid() const { return rigid_ != nullptr; }

 private:
  const PlanningProblem& problem_;
  FclCollisionChecker fcl_;
  std::unique_ptr<RigidDepthChecker> rigid_;
};

// Measures at every waypoint and at `samples` + 1 poses evenly spread over
// the animation time, on every core (each pose is measured alone, so the
// numbers do not depend on how many); `progress` (may be empty) gets the
// poses measured so far and their number.
void MeasurePath(PathEntry* entry, const PoseMeter& meter, int samples, const ProgressCallback& progress = {});

// The path's CSV for the download: the CSV file next to the artifact
// (<stem>.csv, or `also` where given) when it holds the same waypoints,
// else the waypoints written as ausbau's path CSV (17 digits).
void AttachPathCsv(PathEntry* entry, const std::filesystem::path& also);

double MinOf(const std::vector<double>& values);

}  // namespace ausbau::report_internal
