#include "planning/path_io.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/input_file.h"

namespace ausbau {

void AlignQuaternionSigns(std::vector<Pose>* path) {
  for (std::size_t i = 0; i < path->size(); ++i) {
    Eigen::Quaterniond& q = (*path)[i].q;
    const bool flip = i == 0 ? q.w() < 0 : q.coeffs().dot((*path)[i - 1].q.coeffs()) < 0;
    if (flip) q.coeffs() = -q.coeffs();
  }
}

void WritePoseRows(ArtifactWriter& writer, const std::string& name, const std::vector<Pose>& poses,
                   const std::string& units) {
  std::vector<double> rows;
  for (const Pose& p : poses) rows.insert(rows.end(), {p.t.x(), p.t.y(), p.t.z(), p.q.w(), p.q.x(), p.q.y(), p.q.z()});
  writer.WriteDoubles(name, rows, {poses.size(), 7});
  writer.SetAttribute(name, "columns", std::string("x,y,z,qw,qx,qy,qz"));
  const std::string length = LengthUnits(units);
  writer.SetAttribute(name, "units", "x,y,z: " + length + "; qw,qx,qy,qz: unitless (unit quaternion)");
  writer.SetAttribute(name, "pose_convention", std::string(kPoseConvention));
}

std::vector<Pose> ReadPoseRows(const ArtifactReader& reader, const std::string& name) {
  const std::string file = reader.path().string();
  const Array<double> rows = reader.ReadDoubles(name, 2);
  if (rows.dims[1] != 7) {
    throw InputErrorAt(file, "dataset '" + name + "' must have 7 columns (got " + std::to_string(rows.dims[1]) + ")");
  }
  // The reader bounds and checks the element count; index only what was read.
  if (rows.data.size() / 7 != rows.dims[0] || rows.data.size() % 7 != 0) {
    throw InputErrorAt(file,
                       "dataset '" + name + "' holds " + std::to_string(rows.data.size()) + " values, not rows x 7");
  }
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < rows.dims[0]; ++i) {
    const double* r = &rows.data[7 * i];
    for (int k = 0; k < 7; ++k) {
      if (!std::isfinite(r[k])) throw InputErrorAt(file, name + " row " + std::to_string(i) + " is not finite");
    }
    Pose p;
    p.t = {r[0], r[1], r[2]};
    p.q = Eigen::Quaterniond(r[3], r[4], r[5], r[6]);
    if (std::abs(p.q.norm() - 1.0) > 1e-6) {
      throw InputErrorAt(file, name + " row " + std::to_string(i) + " has a non-unit quaternion");
    }
    poses.push_back(p);
  }
  return poses;
}

namespace {

// The attribute `units` of every dataset of a path artifact but the
// waypoints (WritePoseRows): one line per quantity, schemas/path.md.
void WritePathUnits(ArtifactWriter& writer, const PathArtifact& path) {
  const std::string length = LengthUnits(path.units);
  const std::pair<const char*, std::string> units[] = {{"reference_point", length + " (D's mesh coordinates)"},
                                                       {"dynamic_origin", length + " (D's mesh coordinates)"},
                                                       {"stats/success", "boolean (0 or 1)"},
                                                       {"stats/time_s", "s"},
                                                       {"stats/iterations", "count"},
                                                       {"stats/nodes", "count"},
                                                       {"stats/collision_checks", "count"},
                                                       {"stats/invalid_checks", "count"},
                                                       {"stats/length", "unitless (normalized metric)"},
                                                       {"stats/length_translation", length},
                                                       {"stats/length_rotation", "rad"},
                                                       {"stats/clearance", length}};
  for (const auto& [name, unit] : units) writer.SetAttribute(name, "units", unit);
  writer.SetAttribute("", "units", path.units);
  if (!IsVolumeValidity(path.validity)) return;
  const std::pair<const char*, std::string> inistate[] = {
      {"inistate/tau", length + "^3"},
      {"inistate/psi", length},
      {"inistate/inter_index", "index into waypoints"},
      {"inistate/volume", length + "^3"},
      {"inistate/part", "index (D's connected component; -1: none)"},
      {"inistate/deformability", "unitless, 0 rigid .. 1 deformable"}};
  for (const auto& [name, unit] : inistate) writer.SetAttribute(name, "units", unit);
}

}  // namespace

void WritePathArtifact(const std::filesystem::path& file, const PathArtifact& path, const Provenance& provenance) {
  ArtifactWriter writer(file, kPathSchema, kPathSchemaVersion, provenance);
  WritePoseRows(writer, "waypoints", path.waypoints, path.units);
  writer.WriteDoubles("reference_point", {path.reference_point.x(), path.reference_point.y(), path.reference_point.z()},
                      {3});
  writer.WriteDoubles("dynamic_origin", {path.dynamic_origin.x(), path.dynamic_origin.y(), path.dynamic_origin.z()},
                      {3});
  writer.WriteInts("stats/success", {path.success ? 1 : 0}, {});
  writer.WriteDoubles("stats/time_s", {path.stats.time_s}, {});
  writer.WriteInts("stats/iterations", {path.stats.iterations}, {});
  writer.WriteInts("stats/nodes", {path.stats.nodes}, {});
  writer.WriteInts("stats/collision_checks", {path.stats.collision_checks}, {});
  writer.WriteInts("stats/invalid_checks", {path.stats.invalid_checks}, {});
  writer.WriteDoubles("stats/length", {path.length_normalized}, {});
  writer.WriteDoubles("stats/length_translation", {path.length_translation}, {});
  writer.WriteDoubles("stats/length_rotation", {path.length_rotation}, {});
  // Only where there is something to say, so that solved runs' files stay as they were.
  if (!path.partial_waypoints.empty()) WritePoseRows(writer, "partial/waypoints", path.partial_waypoints);
  if (path.stopped_by_budget) writer.WriteInts("stats/stopped_by_budget", {1}, {});
  if (path.smoothing_cut_short) writer.WriteInts("stats/smoothing_cut_short", {1}, {});
  writer.WriteDoubles("stats/clearance", {path.clearance}, {});
  writer.SetAttribute("", "planner", path.planner);
  writer.SetAttribute("", "scene", path.scene);
  writer.SetAttribute("", "validity", ValidityModeName(path.validity));
  if (IsVolumeValidity(path.validity)) {
    const std::size_t n = path.waypoints.size();
    if (path.waypoint_volume.size() != n || path.waypoint_part.size() != n || path.waypoint_deformability.size() != n) {
      throw std::logic_error("WritePathArtifact: per-waypoint volumes do not match the waypoints");
    }
    writer.WriteDoubles("inistate/tau", {path.tau}, {});
    writer.WriteDoubles("inistate/psi", {path.psi}, {});
    writer.WriteInts("inistate/inter_index", {path.inter_index}, {});
    writer.WriteDoubles("inistate/volume", path.waypoint_volume, {n});
    writer.WriteInts("inistate/part", std::vector<std::int64_t>(path.waypoint_part.begin(), path.waypoint_part.end()),
                     {n});
    writer.WriteDoubles("inistate/deformability", path.waypoint_deformability, {n});
  }
  WritePathUnits(writer, path);
  writer.Commit();
}

namespace {

Eigen::Vector3d ReadVector3(const ArtifactReader& reader, const std::string& name) {
  const Array<double> a = reader.ReadDoubles(name, 1);
  if (a.data.size() != 3) throw InputErrorAt(reader.path().string(), "dataset '" + name + "' must hold 3 numbers");
  const Eigen::Vector3d v(a.data[0], a.data[1], a.data[2]);
  if (!v.allFinite()) throw InputErrorAt(reader.path().string(), "dataset '" + name + "' is not finite");
  return v;
}

double ReadScalar(const ArtifactReader& reader, const std::string& name) {
  const Array<double> a = reader.ReadDoubles(name);
  if (a.data.size() != 1) throw InputErrorAt(reader.path().string(), "dataset '" + name + "' must be a scalar");
  return a.data[0];
}

std::int64_t ReadIntScalar(const ArtifactReader& reader, const std::string& name) {
  const Array<std::int64_t> a = reader.ReadInts(name);
  if (a.data.size() != 1) throw InputErrorAt(reader.path().string(), "dataset '" + name + "' must be a scalar");
  return a.data[0];
}

}  // namespace

PathArtifact ReadPathArtifact(const std::filesystem::path& file) {
  const ArtifactReader reader(file, kPathSchema, kPathSchemaVersion);
  PathArtifact path;
  path.waypoints = ReadPoseRows(reader, "waypoints");
  if (path.waypoints.size() > kMaxPathWaypoints) {
    throw InputErrorAt(file.string(), Fmt("holds %zu waypoints, more than the limit of %zu", path.waypoints.size(),
                                          kMaxPathWaypoints));
  }
  path.reference_point = ReadVector3(reader, "reference_point");
  path.dynamic_origin = ReadVector3(reader, "dynamic_origin");
  path.success = ReadIntScalar(reader, "stats/success") != 0;
  path.stats.time_s = ReadScalar(reader, "stats/time_s");
  path.stats.iterations = ReadIntScalar(reader, "stats/iterations");
  path.stats.nodes = ReadIntScalar(reader, "stats/nodes");
  path.stats.collision_checks = ReadIntScalar(reader, "stats/collision_checks");
  path.stats.invalid_checks = ReadIntScalar(reader, "stats/invalid_checks");
  path.length_normalized = ReadScalar(reader, "stats/length");
  // Informational; absent in artifacts written before they were recorded.
  path.length_translation =
      reader.Has("stats/length_translation") ? ReadScalar(reader, "stats/length_translation") : std::nan("");
  path.length_rotation =
      reader.Has("stats/length_rotation") ? ReadScalar(reader, "stats/length_rotation") : std::nan("");
  if (reader.Has("partial/waypoints")) path.partial_waypoints = ReadPoseRows(reader, "partial/waypoints");
  if (path.partial_waypoints.size() > kMaxPathWaypoints) {
    throw InputErrorAt(file.string(), Fmt("holds %zu partial waypoints, more than the limit of %zu",
                                          path.partial_waypoints.size(), kMaxPathWaypoints));
  }
  path.stopped_by_budget =
      reader.Has("stats/stopped_by_budget") && ReadIntScalar(reader, "stats/stopped_by_budget") != 0;
  path.smoothing_cut_short =
      reader.Has("stats/smoothing_cut_short") && ReadIntScalar(reader, "stats/smoothing_cut_short") != 0;
  // Absent in artifacts written before they were recorded.
  path.clearance = reader.Has("stats/clearance") ? ReadScalar(reader, "stats/clearance") : std::nan("");
  if (!std::isnan(path.clearance) && !(std::isfinite(path.clearance) && path.clearance >= 0)) {
    throw InputErrorAt(file.string(), "dataset 'stats/clearance' is not a finite number >= 0");
  }
  path.planner = reader.ReadStringAttribute("", "planner");
  path.scene = reader.ReadStringAttribute("", "scene");
  path.validity =
      ParseValidityMode(reader.ReadStringAttribute("", "validity"), file.string() + ": attribute 'validity'");
  if (reader.Has("inistate/volume")) {
    path.tau = ReadScalar(reader, "inistate/tau");
    path.psi = ReadScalar(reader, "inistate/psi");
    const std::int64_t inter_index = ReadIntScalar(reader, "inistate/inter_index");
    // Checked against the waypoints below; out of int range it would wrap.
    path.inter_index =
        inter_index < -1 || inter_index > std::numeric_limits<int>::max() ? -2 : static_cast<int>(inter_index);
    path.waypoint_volume = reader.ReadDoubles("inistate/volume", 1).data;
    for (std::int64_t part : reader.ReadInts("inistate/part", 1).data) {
      // Out of int range would wrap into a plausible index.
      if (part < -1 || part > std::numeric_limits<int>::max()) {
        throw InputErrorAt(file.string(), "dataset 'inistate/part' holds an index out of range");
      }
      path.waypoint_part.push_back(static_cast<int>(part));
    }
    path.waypoint_deformability = reader.ReadDoubles("inistate/deformability", 1).data;
    const std::size_t n = path.waypoints.size();
    if (path.waypoint_volume.size() != n || path.waypoint_part.size() != n || path.waypoint_deformability.size() != n ||
        path.inter_index < -1 || path.inter_index >= static_cast<int>(n)) {
      throw InputErrorAt(file.string(), "inistate datasets do not match the waypoints");
    }
    // A verdict trusts these numbers: NaN or a negative volume must not pass.
    if (!std::isfinite(path.tau) || !std::isfinite(path.psi)) {
      throw InputErrorAt(file.string(), "dataset 'inistate/tau' or 'inistate/psi' is not finite");
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!(std::isfinite(path.waypoint_volume[i]) && path.waypoint_volume[i] >= 0)) {
        throw InputErrorAt(file.string(),
                           "dataset 'inistate/volume' holds a negative or non-finite value at " + std::to_string(i));
      }
      if (path.waypoint_part[i] < -1) {
        throw InputErrorAt(file.string(), "dataset 'inistate/part' holds a negative index at " + std::to_string(i));
      }
    }
  }
  return path;
}

std::vector<Pose> ReadPathCsv(const std::filesystem::path& file) {
  // A FIFO would block, a device never end (CheckInputFile).
  CheckInputFile(file, kMaxTextInputBytes, "path CSV");
  std::ifstream in(file);
  if (!in) throw InputErrorAt(file.string(), "cannot be read");
  std::string line;
  std::vector<int> column;  // index of x,y,z,qw,qx,qy,qz
  std::vector<Pose> poses;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) {
      cell.erase(0, cell.find_first_not_of(" \t"));
      cell.erase(cell.find_last_not_of(" \t") + 1);
      cells.push_back(cell);
    }
    if (column.empty()) {
      for (const char* name : {"x", "y", "z", "qw", "qx", "qy", "qz"}) {
        const auto it = std::find(cells.begin(), cells.end(), name);
        if (it == cells.end()) throw InputErrorAt(file.string(), Fmt("header lacks column '%s'", name));
        column.push_back(static_cast<int>(it - cells.begin()));
      }
      continue;
    }
    double v[7];
    for (int k = 0; k < 7; ++k) {
      char* end = nullptr;
      const std::string& cell = column[k] < static_cast<int>(cells.size()) ? cells[column[k]] : std::string();
      v[k] = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || !std::isfinite(v[k]))
        throw InputErrorAt(file.string(), Fmt("line %d: not a finite number in column %d", number, column[k] + 1));
    }
    Pose pose;
    pose.t = {v[0], v[1], v[2]};
    pose.q = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
    if (std::abs(pose.q.norm() - 1) > 1e-3)
      throw InputErrorAt(file.string(), Fmt("line %d: not a unit quaternion", number));
    pose.q.normalize();
    poses.push_back(pose);
  }
  if (column.empty()) throw InputErrorAt(file.string(), "no header (x,y,z,qw,qx,qy,qz)");
  return poses;
}

void WritePathCsv(const std::filesystem::path& file, const std::vector<Pose>& waypoints) {
  std::string text = "x,y,z,qw,qx,qy,qz\n";
  char line[512];
  for (const Pose& p : waypoints) {
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", p.t.x(), p.t.y(), p.t.z(), p.q.w(),
                  p.q.x(), p.q.y(), p.q.z());
    text += line;
  }
  WriteTextFileAtomically(file, text);
}

}  // namespace ausbau

namespace ausbau {

void WriteOmplPath(const std::filesystem::path& file, const std::vector<Pose>& waypoints) {
  std::string text;
  char line[512];
  for (const Pose& p : waypoints) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", p.t.x(), p.t.y(), p.t.z(), p.q.x(),
                  p.q.y(), p.q.z(), p.q.w());
    text += line;
  }
  WriteTextFileAtomically(file, text);
}

}  // namespace ausbau
