// Path artifacts (schema ausbau-path, see schemas/path.md) and exports.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "core/atomic_file.h"
#include "planning/planner.h"
#include "planning/validity_mode.h"

namespace ausbau {

inline constexpr char kPathSchema[] = "ausbau-path";
inline constexpr int kPathSchemaVersion = 1;
// The most waypoints a path artifact may hold (`waypoints`, and
// `partial/waypoints`). Planned and smoothed paths hold tens to a few
// thousand; a path of a million made ausbau-smooth run past 600 s and
// ausbau-report write 175 MB, so readers refuse more than this.
inline constexpr std::size_t kMaxPathWaypoints = 100000;

struct PathArtifact {
  std::vector<Pose> waypoints;                                // scene convention
  Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();  // interpolation centre, D's mesh coordinates
  Eigen::Vector3d dynamic_origin = Eigen::Vector3d::Zero();
  std::string planner;
  std::string scene;
  bool success = false;
  PlanStats stats;
  double length_normalized = 0;
  double length_translation = 0;
  double length_rotation = 0;
  // The scene's `units` (every length in the file is in them; written as
  // the attribute `units` of each dataset), and the clearance from S the
  // path was planned or smoothed to keep where it could (--clearance,
  // scene units; 0: none; NaN when read from a file that predates it).
  std::string units;
  double clearance = 0;

  // InIState planning (optional datasets, group `inistate`; absent for
  // rigid planning): the validity mode and threshold, psi, the index of
  // c_inter (end of sigma_1), and per waypoint the mode's volume, the part
  // of D it belongs to and that component's mean deformability.
  ValidityMode validity = ValidityMode::kCollision;
  double tau = 0, psi = 0;
  int inter_index = -1;
  std::vector<double> waypoint_volume;
  std::vector<int> waypoint_part;
  std::vector<double> waypoint_deformability;

  // An unsolved run (success = false): the best partial path (scene
  // convention; from the start to the planner's node with the most progress,
  // planning/planner.h: PartialProgress), and whether a clock (the time
  // limit, a safety net, or the budget: --budget / --deadline) ended the
  // search. Optional datasets `partial/` and `stats/stopped_by_budget`;
  // absent in older files.
  std::vector<Pose> partial_waypoints;
  bool stopped_by_budget = false;
  // A smoothed path (ausbau-smooth): the smoothing's time limit (a safety
  // net) or the budget stopped it before its counted work was done. The
  // path is valid (every change is checked) but not the deterministic one.
  // Optional dataset `stats/smoothing_cut_short`.
  bool smoothing_cut_short = false;
};

// The one pose convention of every file Ausbau writes (path.h5, path.csv,
// path-smooth.*, profile.csv, the OMPL path): schemas/scene.md "Pose
// convention". Written into each of them.
inline constexpr char kPoseConvention[] = "x_world = R(q) (x_mesh - dynamic_origin) + t";

// The unit text of a length in scene units: the scene's `units`, or
// "scene units" where the scene names none.
inline std::string LengthUnits(const std::string& units) { return units.empty() ? "scene units" : units; }

// Makes consecutive quaternions lie in the same hemisphere (q and -q are one
// rotation), so that any reader's interpolation takes the short way.
void AlignQuaternionSigns(std::vector<Pose>* path);

// Poses as an n x 7 dataset (x,y,z,qw,qx,qy,qz) of an artifact, written and
// read back checked (finite, unit quaternions; InputError naming `name`).
// Written with the attributes `columns`, `units` (x,y,z in `units`, the
// quaternion unitless) and `pose_convention` (kPoseConvention).
void WritePoseRows(ArtifactWriter& writer, const std::string& name, const std::vector<Pose>& poses,
                   const std::string& units = "");
std::vector<Pose> ReadPoseRows(const ArtifactReader& reader, const std::string& name);

void WritePathArtifact(const std::filesystem::path& file, const PathArtifact& path, const Provenance& provenance);
PathArtifact ReadPathArtifact(const std::filesystem::path& file);

// CSV with header x,y,z,qw,qx,qy,qz, one waypoint per row, 17 significant
// digits; written atomically.
void WritePathCsv(const std::filesystem::path& file, const std::vector<Pose>& waypoints);

// Reads a path CSV as any tool would: lines starting with '#' skipped, a
// header naming x,y,z,qw,qx,qy,qz (any order, other columns ignored), one
// pose per row. Throws InputError naming the file and line.
std::vector<Pose> ReadPathCsv(const std::filesystem::path& file);

// OMPL's path text format: one state per line, "x y z qx qy qz qw" (the
// pose of the reference point OMPL.app uses, i.e. the scene convention when
// dynamic_origin is D's centroid as in the OMPL.app scenes).
void WriteOmplPath(const std::filesystem::path& file, const std::vector<Pose>& waypoints);

}  // namespace ausbau
