#include "report/report_paths.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "artifact/artifact.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/format.h"
#include "report/report_util.h"

namespace ausbau::report_internal {

namespace fs = std::filesystem;

PathEntry LoadPath(const std::string& key, const fs::path& file) {
  PathEntry entry;
  entry.key = key;
  entry.file = file;
  entry.artifact = ReadPathArtifact(file);
  const ArtifactReader reader(file, kPathSchema, kPathSchemaVersion);
  entry.producer = reader.producer();
  if (reader.Has("stats/length_translation")) {
    const auto a = reader.ReadDoubles("stats/length_translation");
    if (a.data.size() == 1) entry.length_translation = a.data[0];
  }
  if (reader.Has("stats/length_rotation")) {
    const auto a = reader.ReadDoubles("stats/length_rotation");
    if (a.data.size() == 1) entry.length_rotation = a.data[0];
  }
  return entry;
}

// World position of the artifact's reference point at a scene-convention pose.
Pose ToReference(const PathArtifact& path, const Pose& scene_pose) {
  Pose out = scene_pose;
  out.t = scene_pose.t + scene_pose.q * (path.reference_point - path.dynamic_origin);
  return out;
}

Pose FromReference(const PathArtifact& path, const Pose& reference_pose) {
  Pose out = reference_pose;
  out.t = reference_pose.t - reference_pose.q * (path.reference_point - path.dynamic_origin);
  return out;
}

// The animation runs at constant "speed": each segment takes time in
// proportion to how far the points of D move at most (translation of the
// reference point plus radius x rotation angle).
std::vector<double> AnimationTimes(const PathArtifact& path, const TriangleMesh& robot_mesh) {
  const std::size_t n = path.waypoints.size();
  std::vector<double> times(n, 0.0);
  if (n < 2) return times;
  double radius = 0;
  for (const Eigen::Vector3d& v : robot_mesh.vertices) radius = std::max(radius, (v - path.reference_point).norm());
  std::vector<double> lengths(n - 1);
  double total = 0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    lengths[i] =
        MaxDisplacement(ToReference(path, path.waypoints[i]), ToReference(path, path.waypoints[i + 1]), radius);
    total += lengths[i];
  }
  for (std::size_t i = 1; i < n; ++i) {
    times[i] = total > 0 ? times[i - 1] + lengths[i - 1] / total : static_cast<double>(i) / (n - 1);
  }
  times[n - 1] = 1.0;
  return times;
}

// The scene-convention pose at animation time u, interpolated as
// schemas/path.md says: linear in the reference point's position, slerp in q.
Pose PoseAtTime(const PathArtifact& path, const std::vector<double>& times, double u) {
  const std::size_t n = path.waypoints.size();
  if (n == 1 || u <= 0) return path.waypoints.front();
  if (u >= 1) return path.waypoints.back();
  std::size_t i = std::upper_bound(times.begin(), times.end(), u) - times.begin();
  i = std::clamp<std::size_t>(i, 1, n - 1) - 1;
  const double span = times[i + 1] - times[i];
  const double s = span > 0 ? std::clamp((u - times[i]) / span, 0.0, 1.0) : 0.0;
  const Pose a = ToReference(path, path.waypoints[i]);
  const Pose b = ToReference(path, path.waypoints[i + 1]);
  return FromReference(path, Interpolate(a, b, s));
}

PoseMeter::PoseMeter(const PlanningProblem& problem, std::shared_ptr<const PartModel> parts, double tolerance)
    : problem_(problem), fcl_(problem.robot, problem.environment) {
  if (parts) rigid_ = std::make_unique<RigidDepthChecker>(std::move(parts), tolerance, tolerance / 10);
}

PoseMeasure PoseMeter::Measure(const Pose& scene_pose) const {
  PoseMeasure m;
  const FclCollisionChecker::Nearest nearest = fcl_.NearestTriangles(problem_.SceneToPlanning(scene_pose));
  m.clearance = nearest.distance;
  m.robot_triangle = nearest.robot_triangle;
  m.static_triangle = nearest.environment_triangle;
  if (rigid_) {
    const DepthReport depth = rigid_->Measure(scene_pose);
    m.rigid_depth = depth.rigid_depth;
    m.fastener_depth = depth.fastener_depth;
    if (depth.rigid_depth > 0) {
      m.rigid_shell = depth.rigid_shell;
      m.static_shell = depth.rigid_static_shell;
    }
  }
  return m;
}

void MeasurePath(PathEntry* entry, const PoseMeter& meter, int samples, const ProgressCallback& progress) {
  const PathArtifact& path = entry->artifact;
  if (path.waypoints.empty()) return;
  std::vector<Pose> poses = path.waypoints;
  if (path.waypoints.size() >= 2 && samples > 0) {
    for (int k = 0; k <= samples; ++k) {
      const double u = static_cast<double>(k) / samples;
      entry->sample_times.push_back(u);
      poses.push_back(PoseAtTime(path, entry->times, u));
    }
  }
  // A depth measure in contact on a finely tessellated part takes 0.1 s
  // (as1's bolt at 0.001 mm deflection: 55 s for its two paths on one
  // core), so in parallel, in chunks between which the progress shows.
  std::vector<PoseMeasure> measured(poses.size());
  constexpr std::ptrdiff_t kChunk = 16;
  const auto count = static_cast<std::ptrdiff_t>(poses.size());
  for (std::ptrdiff_t begin = 0; begin < count; begin += kChunk) {
    ThrowIfCancelled();
    const std::ptrdiff_t end = std::min(count, begin + kChunk);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t i = begin; i < end; ++i) measured[i] = meter.Measure(poses[i]);
    if (progress) progress(end, count);
  }
  const auto waypoints = measured.begin() + static_cast<std::ptrdiff_t>(path.waypoints.size());
  entry->at_waypoints.assign(measured.begin(), waypoints);
  entry->at_samples.assign(waypoints, measured.end());
}

namespace {

std::string CsvOf(const std::vector<Pose>& waypoints) {
  std::string text = "x,y,z,qw,qx,qy,qz\n";
  for (const Pose& p : waypoints) {
    text += Fmt("%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", p.t.x(), p.t.y(), p.t.z(), p.q.w(), p.q.x(), p.q.y(),
                p.q.z());
  }
  return text;
}

// The same waypoints, up to the digits a CSV keeps (and q or -q).
bool SameWaypoints(const std::vector<Pose>& a, const std::vector<Pose>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double scale = 1.0 + a[i].t.norm();
    if ((a[i].t - b[i].t).norm() > 1e-9 * scale) return false;
    if (std::abs(std::abs(a[i].q.dot(b[i].q)) - 1.0) > 1e-9) return false;
  }
  return true;
}

}  // namespace

void AttachPathCsv(PathEntry* entry, const fs::path& also) {
  fs::path sibling = entry->file;
  sibling.replace_extension(".csv");
  for (const fs::path& candidate : {also, sibling}) {
    if (candidate.empty() || !IsOwnRegularFile(candidate)) continue;  // a link could point anywhere
    try {
      if (!SameWaypoints(ReadPathCsv(candidate), entry->artifact.waypoints)) continue;
      entry->csv_text = ReadTextFile(candidate);
      entry->csv_name = candidate.filename().string();
      return;
    } catch (const InputError&) {
      continue;
    }
  }
  entry->csv_text = CsvOf(entry->artifact.waypoints);
  entry->csv_name = sibling.filename().string();
}

double MinOf(const std::vector<double>& values) {
  double m = std::numeric_limits<double>::infinity();
  for (double v : values) m = std::min(m, v);
  return m;
}

}  // namespace ausbau::report_internal
