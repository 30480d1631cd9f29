#include "report/report.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "artifact/artifact.h"
#include "artifact/run_files.h"
#include "collision/scene_parts.h"
#include "core/error.h"
#include "core/format.h"
#include "core/log.h"
#include "labeling/pbd_label.h"
#include "planning/path_io.h"
#include "planning/state_space.h"
#include "report/json_read.h"
#include "report/report_headline.h"
#include "report/report_page.h"
#include "report/report_parts.h"
#include "report/report_paths.h"
#include "report/report_profile.h"
#include "report/report_util.h"
#include "scene/scene.h"

namespace ausbau {

using namespace report_internal;
namespace fs = std::filesystem;

// ----------------------------------------------------------------- helpers

std::string Base64Encode(const void* data, std::size_t size) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* in = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t v = (in[i] << 16) | (in[i + 1] << 8) | in[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < size) {
    std::uint32_t v = in[i] << 16;
    if (i + 1 < size) v |= in[i + 1] << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string HtmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default:
        // A control character from a name (an escape sequence in a file's
        // name) is shown, as on the terminal (core/format.h TerminalSafe).
        if ((static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t' && c != '\r') || c == 0x7f) {
          out += Fmt("\\x%02x", static_cast<unsigned char>(c));
        } else {
          out += c;
        }
    }
  }
  return out;
}

namespace {

using Artifacts = std::vector<std::pair<std::string, std::string>>;  // name, status (HTML)

std::string MeshJson(const TriangleMesh& mesh, const Eigen::Vector3d& shift, BufferStore* store) {
  std::vector<float> positions;
  positions.reserve(mesh.vertices.size() * 3);
  for (const Eigen::Vector3d& v : mesh.vertices) {
    const Eigen::Vector3d p = v - shift;  // in double, then rounded once
    positions.insert(positions.end(),
                     {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
  }
  std::vector<std::uint32_t> indices;
  indices.reserve(mesh.triangles.size() * 3);
  for (const auto& tri : mesh.triangles) {
    for (int i : tri) indices.push_back(static_cast<std::uint32_t>(i));
  }
  return "{\"positions\":" + store->Add(Float32Bytes(positions), "f32", positions.size()) +
         ",\"indices\":" + store->Add(Uint32Bytes(indices), "u32", indices.size()) +
         Fmt(",\"vertices\":%zu,\"triangles\":%zu}", mesh.vertices.size(), mesh.triangles.size());
}

// The files of a report: given one by one, or found by name in a run
// folder (the command line's files win). What a run folder lacks is noted
// in the summary and in `artifacts` (name, status as HTML).
struct ReportFiles {
  fs::path path_file, smoothed_file, labels_file, verdict_file, spheres_file, profile_file, path_csv;
};

ReportFiles FindReportFiles(const ReportOptions& options, ReportSummary* summary,
                            std::vector<std::pair<std::string, std::string>>* artifacts_out) {
  std::vector<std::pair<std::string, std::string>>& artifacts = *artifacts_out;
  ReportFiles files;
  fs::path& path_file = files.path_file;
  fs::path& smoothed_file = files.smoothed_file;
  fs::path& labels_file = files.labels_file;
  fs::path& verdict_file = files.verdict_file;
  fs::path& spheres_file = files.spheres_file;
  path_file = options.path;
  smoothed_file = options.smoothed;
  std::string absent;
  if (!options.run_dir.empty()) {
    std::error_code ec;
    if (!fs::is_directory(options.run_dir, ec)) throw InputErrorAt(options.run_dir.string(), "run folder not found");
    // A symbolic link in the run folder is not followed: it may point at
    // any file the user can read (stages write regular files only).
    auto linked = [&](const fs::path& candidate) {
      if (!IsSymbolicLink(candidate)) return false;
      const std::string note = candidate.string() + ": is a symbolic link; not followed (left out of the report)";
      LogWarn("%s", note.c_str());
      summary->notes.push_back(note);
      return true;
    };
    auto pick = [&](const char* name, fs::path* slot, bool explicit_given) {
      const fs::path candidate = options.run_dir / name;
      if (explicit_given) {
        artifacts.emplace_back(name, "replaced by the command line's file");
      } else if (IsOwnRegularFile(candidate)) {
        *slot = candidate;
      } else if (linked(candidate)) {
        artifacts.emplace_back(name, "<span class=\"note\">ignored: a symbolic link</span>");
      } else {
        artifacts.emplace_back(name, "absent");
        absent += std::string(absent.empty() ? "" : ", ") + name;
      }
    };
    pick(kRunFilePath, &path_file, !options.path.empty());
    pick(kRunFilePathSmooth, &smoothed_file, !options.smoothed.empty());
    pick(kRunFileLabels, &labels_file, false);
    pick(kRunFileSpheres, &spheres_file, false);
    pick(kRunFileVerdict, &verdict_file, false);
    pick(kRunFileProfile, &files.profile_file, false);
    if (IsOwnRegularFile(options.run_dir / kRunFilePathCsv)) {
      files.path_csv = options.run_dir / kRunFilePathCsv;
    } else {
      linked(options.run_dir / kRunFilePathCsv);
    }
    if (!absent.empty()) summary->notes.push_back("not in " + options.run_dir.string() + ": " + absent);
  }

  return files;
}

// D's labels for the viewer (deformability per vertex, as float32 in the
// buffer store), or "null". Labels that do not fit D are ignored with a
// note, not an error: the report still shows the path.
std::string LabelsJson(const fs::path& labels_file, const Scene& scene, BufferStore* store_out, ReportSummary* summary,
                       std::vector<std::pair<std::string, std::string>>* artifacts_out) {
  BufferStore& store = *store_out;
  std::vector<std::pair<std::string, std::string>>& artifacts = *artifacts_out;
  std::string labels_json = "null";
  if (!labels_file.empty()) {
    try {
      // The labels' schema has one owner (labeling/pbd_label.h); the viewer
      // needs floats (colours).
      const LabelsArtifact stored = ReadLabelsArtifact(labels_file);
      Array<float> values;
      values.dims = {stored.deformability.size()};
      values.data.assign(stored.deformability.begin(), stored.deformability.end());
      if (values.data.size() != scene.dynamic_mesh.vertices.size()) {
        throw InputErrorAt(labels_file.string(),
                           Fmt("dataset 'deformability' has %zu values (expected one per vertex of D: %zu)",
                               values.data.size(), scene.dynamic_mesh.vertices.size()));
      }
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      for (float v : values.data) {
        if (!std::isfinite(v))
          throw InputErrorAt(labels_file.string(), "dataset 'deformability' holds a non-finite value");
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      labels_json = "{\"name\":\"deformability\",\"file\":" + JsonString(labels_file.string()) +
                    ",\"min\":" + JsonNumber(lo) + ",\"max\":" + JsonNumber(hi) +
                    ",\"values\":" + store.Add(Float32Bytes(values.data), "f32", values.data.size()) + "}";
      summary->used.push_back("labels: " + labels_file.string());
      artifacts.emplace_back(kRunFileLabels, "used: D coloured by deformability");
    } catch (const InputError& e) {
      LogWarn("labels ignored: %s", e.what());
      summary->notes.push_back(std::string("labels ignored: ") + e.what());
      artifacts.emplace_back(kRunFileLabels, "<span class=\"note\">ignored: " + HtmlEscape(e.what()) + "</span>");
    }
  }
  return labels_json;
}

// verdict.json as it is, for the page's tables; an
// unreadable one is noted and left out. The verdict is also parsed (for the
// headline) into `verdict`, or `verdict_problem` says why not.
std::string JsonFilesJson(const ReportFiles& files, ReportSummary* summary, Artifacts* artifacts,
                          std::optional<JsonValue>* verdict, std::string* verdict_problem) {
  *verdict_problem = "no verdict.json";
  std::string json_files = "[";
  for (const auto& [name, file] : {std::pair<std::string, fs::path>{"verdict", files.verdict_file}}) {
    if (file.empty()) continue;
    std::string text;
    try {
      text = ReadTextFile(file);
    } catch (const InputError& e) {
      summary->notes.push_back(e.what());
      artifacts->emplace_back(file.filename().string(),
                              "<span class=\"note\">ignored: " + HtmlEscape(e.what()) + "</span>");
      if (name == "verdict") *verdict_problem = e.what();
      continue;
    }
    if (name == "verdict") {
      JsonValue parsed;
      std::string error;
      if (ParseJson(text, &parsed, &error)) {
        *verdict = std::move(parsed);
      } else {
        *verdict_problem = file.string() + " is not JSON (" + error + ")";
        summary->notes.push_back(*verdict_problem);
      }
    }
    json_files += (json_files.size() > 1 ? "," : "") +
                  ("{\"name\":" + JsonString(name) + ",\"file\":" + JsonString(file.string()) +
                   ",\"text\":" + JsonString(text) + "}");
    summary->used.push_back(name + ": " + file.string());
    artifacts->emplace_back(file.filename().string(), "used: shown as a table");
  }
  return json_files + "]";
}

// The rigid model the report measures with: the verdict's tolerance and
// validity where it has them (else 0.05 mm in the scene's units, exact).
std::shared_ptr<const PartModel> RigidModel(const Scene& scene, const JsonValue* verdict, double* tolerance) {
  bool assumed = false;
  *tolerance = RigidToleranceInSceneUnits(0.05, scene.units, &assumed);
  UnmeasuredInterference unmeasured = UnmeasuredInterference::kRigid;
  if (verdict != nullptr) {
    const JsonValue* t = verdict->At("exact_check.rigid_tolerance");
    if (t != nullptr && t->IsNumber() && t->number > 0) *tolerance = t->number;
    const JsonValue* validity = verdict->Find("validity");
    if (validity != nullptr && validity->IsString() && validity->string != "rigid-exact" &&
        validity->string != "collision") {
      unmeasured = UnmeasuredInterference::kFastener;  // a volume model bounded those while planning
    }
  }
  return ClassifySceneParts(scene, *tolerance, unmeasured);
}

// One plot's series: values at the dense samples (x) and at the waypoints.
std::string SeriesJson(const char* name, const std::string& label, const std::string& unit, const PathEntry& e,
                       double (*value)(const PoseMeasure&)) {
  std::vector<double> y, w;
  for (const PoseMeasure& m : e.at_samples) y.push_back(value(m));
  for (const PoseMeasure& m : e.at_waypoints) w.push_back(value(m));
  return "{\"name\":" + JsonString(name) + ",\"label\":" + JsonString(label) + ",\"unit\":" + JsonString(unit) +
         ",\"x\":" + JsonNumbers(e.sample_times) + ",\"y\":" + JsonNumbers(y) + ",\"waypoints\":" + JsonNumbers(w) +
         "}";
}

double ClearanceOf(const PoseMeasure& m) { return m.clearance; }
// Rigid penetration: 0 where the rigid part is clear of S; null (not finite)
// where an unmeasured pair intersects.
double RigidOf(const PoseMeasure& m) {
  return std::isnan(m.rigid_depth) ? m.rigid_depth : std::max(0.0, m.rigid_depth);
}
double ClipOf(const PoseMeasure& m) { return m.fastener_depth; }

// The volume model's intersection along the path (profile.csv), placed on
// the animation time by each row's segment and fraction.
std::string VolumeSeriesJson(const Profile& profile, const PathEntry& e, const std::string& units,
                             std::vector<double>* at_waypoints) {
  std::vector<double> x, y;
  at_waypoints->assign(e.artifact.waypoints.size(), std::nan(""));
  for (const ProfileRow& row : profile.rows) {
    const std::size_t i = static_cast<std::size_t>(row.segment);
    const double u = e.times[i] + row.fraction * (e.times[i + 1] - e.times[i]);
    x.push_back(u);
    y.push_back(row.volume);
    if (row.fraction >= 1.0) (*at_waypoints)[i + 1] = row.volume;
    if (row.fraction <= 0.0) (*at_waypoints)[i] = row.volume;
  }
  return "{\"name\":\"volume\",\"label\":" +
         JsonString("clip intersection volume (volume model; profile.csv '" + profile.volume_column + "')") +
         ",\"unit\":" + JsonString(VolumeUnit(units)) + ",\"x\":" + JsonNumbers(x) + ",\"y\":" + JsonNumbers(y) +
         ",\"waypoints\":" + JsonNumbers(*at_waypoints) + "}";
}

// Per waypoint: clearance, rigid and clip depth, volume, and the parts of D
// and S that touch (rigid penetration) or are nearest; names interned.
std::string WaypointTableJson(const PathEntry& e, const PartNamer& namer, const std::vector<double>& volumes) {
  std::vector<std::string> names;
  auto intern = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return static_cast<int>(it - names.begin());
    names.push_back(name);
    return static_cast<int>(names.size() - 1);
  };
  std::string rows = "[";
  for (std::size_t i = 0; i < e.at_waypoints.size(); ++i) {
    const PoseMeasure& m = e.at_waypoints[i];
    const bool contact = m.rigid_shell >= 0;
    const int d = intern(contact ? namer.Shell(m.rigid_shell, true) : namer.Triangle(m.robot_triangle, true));
    const int s = intern(contact ? namer.Shell(m.static_shell, false) : namer.Triangle(m.static_triangle, false));
    rows += (i ? "," : "") +
            ("[" + JsonNumber(m.clearance) + "," + JsonNumber(RigidOf(m)) + "," + JsonNumber(m.fastener_depth) + "," +
             JsonNumber(i < volumes.size() ? volumes[i] : std::nan("")) + "," +
             Fmt("%d,%d,%s]", d, s, contact || m.clearance <= 0 ? "true" : "false"));
  }
  std::string names_json = "[";
  for (std::size_t k = 0; k < names.size(); ++k) names_json += (k ? "," : "") + JsonString(names[k]);
  return "{\"columns\":[\"clearance\",\"rigid\",\"clip\",\"volume\",\"d_part\",\"s_part\",\"contact\"],\"names\":" +
         names_json + "],\"rows\":" + rows + "]}";
}

std::string PathJson(const PathEntry& e, const std::string& units, const PartNamer& namer, bool rigid,
                     const Profile* profile) {
  const PathArtifact& p = e.artifact;
  std::string wp = "[";
  for (std::size_t i = 0; i < p.waypoints.size(); ++i) wp += (i ? "," : "") + JsonPose(p.waypoints[i]);
  wp += "]";
  std::string series = "[";
  std::vector<double> volumes;
  if (!e.at_waypoints.empty()) {
    const std::string unit = LengthUnit(units);
    series += SeriesJson("clearance", "clearance (FCL distance between D and S)", unit, e, ClearanceOf);
    if (rigid) {
      series +=
          "," + SeriesJson("rigid", "rigid penetration (deepest rigid shell of D into S; exact)", unit, e, RigidOf);
      series += "," + SeriesJson("clip", "clip intersection (deepest fastener shell of D into S)", unit, e, ClipOf);
    }
    if (profile != nullptr) series += "," + VolumeSeriesJson(*profile, e, units, &volumes);
  }
  series += "]";
  return "{\"key\":" + JsonString(e.key) + ",\"file\":" + JsonString(e.file.string()) +
         ",\"success\":" + (p.success ? "true" : "false") + ",\"reference_point\":" + JsonVector(p.reference_point) +
         ",\"dynamic_origin\":" + JsonVector(p.dynamic_origin) + ",\"waypoints\":" + wp +
         ",\"times\":" + JsonNumbers(e.times) + ",\"series\":" + series +
         ",\"table\":" + WaypointTableJson(e, namer, volumes) + ",\"csv_name\":" + JsonString(e.csv_name) + "}";
}

// profile.csv of the smoothed path, when it fits that path; else null with
// a note.
std::optional<Profile> LoadProfile(const fs::path& file, const std::vector<PathEntry>& paths, ReportSummary* summary,
                                   Artifacts* artifacts) {
  if (file.empty()) return std::nullopt;
  const auto smoothed =
      std::find_if(paths.begin(), paths.end(), [](const PathEntry& e) { return e.key == "smoothed"; });
  std::string problem;
  std::optional<Profile> profile;
  try {
    profile = ReadProfileCsv(file);
    const std::size_t n = smoothed == paths.end() ? 0 : smoothed->artifact.waypoints.size();
    for (const ProfileRow& row : profile->rows) {
      if (static_cast<std::size_t>(row.segment) + 1 >= n) {
        problem = file.string() + ": segment " + std::to_string(row.segment) + " is not a segment of the smoothed path";
        break;
      }
    }
  } catch (const InputError& e) {
    problem = e.what();
  }
  if (problem.empty() && !profile->has_volume) {
    artifacts->emplace_back(file.filename().string(), "used: no volume values (not a volume mode)");
    return std::nullopt;
  }
  if (!problem.empty()) {
    summary->notes.push_back("profile ignored: " + problem);
    artifacts->emplace_back(file.filename().string(),
                            "<span class=\"note\">ignored: " + HtmlEscape(problem) + "</span>");
    return std::nullopt;
  }
  summary->used.push_back("profile: " + file.string());
  artifacts->emplace_back(file.filename().string(), "used: the intersection volume plot");
  return profile;
}

// The planned and smoothed paths of the run, checked to belong to `scene`,
// with their animation times and the path CSV to download.
std::vector<PathEntry> LoadReportPaths(const ReportFiles& files, const Scene& scene, const PlanningProblem& problem,
                                       ReportSummary* summary, Artifacts* artifacts) {
  std::vector<PathEntry> paths;
  if (!files.path_file.empty()) paths.push_back(LoadPath("planned", files.path_file));
  if (!files.smoothed_file.empty()) paths.push_back(LoadPath("smoothed", files.smoothed_file));
  const double tolerance = 1e-9 * (1.0 + problem.robot_diagonal);
  for (PathEntry& e : paths) {
    if ((e.artifact.dynamic_origin - scene.dynamic_origin).norm() > tolerance) {
      throw InputErrorAt(e.file.string(), "belongs to another scene: its dynamic_origin " +
                                              VectorText(e.artifact.dynamic_origin) + " differs from the scene's " +
                                              VectorText(scene.dynamic_origin));
    }
    if (!e.artifact.scene.empty() && e.artifact.scene != scene.name) {
      summary->notes.push_back(e.file.string() + ": planned for scene '" + e.artifact.scene + "', shown in '" +
                               scene.name + "'");
    }
    e.times = AnimationTimes(e.artifact, scene.dynamic_mesh);
    AttachPathCsv(&e, e.key == "smoothed" ? files.path_csv : fs::path());
    summary->used.push_back(e.key + " path: " + e.file.string());
    artifacts->emplace_back(e.file.filename().string(), "used: " + e.key + " path");
  }
  return paths;
}

}  // namespace

std::string BuildReportHtml(const ReportOptions& options, const ReportAssets& assets, ReportSummary* summary) {
  ReportSummary local;
  if (!summary) summary = &local;
  if (options.scene.empty()) throw InputError("--scene is required");
  Artifacts artifacts;
  const ReportFiles files = FindReportFiles(options, summary, &artifacts);

  const Scene scene = LoadScene(options.scene);
  const PlanningProblem problem = MakePlanningProblem(scene);
  summary->used.push_back("scene: " + options.scene.string());
  std::vector<PathEntry> paths = LoadReportPaths(files, scene, problem, summary, &artifacts);

  BufferStore store;
  const std::string labels_json = LabelsJson(files.labels_file, scene, &store, summary, &artifacts);
  if (!files.spheres_file.empty()) artifacts.emplace_back(kRunFileSpheres, "present (not shown by this version)");
  std::optional<JsonValue> verdict;
  std::string verdict_problem;
  const std::string json_files = JsonFilesJson(files, summary, &artifacts, &verdict, &verdict_problem);
  const std::optional<Profile> profile = LoadProfile(files.profile_file, paths, summary, &artifacts);

  // Measured along each path: clearance, rigid and clip depth, parts.
  double tolerance = 0;
  std::shared_ptr<const PartModel> parts;
  if (!paths.empty()) parts = RigidModel(scene, verdict ? &*verdict : nullptr, &tolerance);
  const PartNamer namer(scene, parts);
  if (!paths.empty()) {
    const PoseMeter meter(problem, parts, tolerance);
    for (PathEntry& e : paths)
      MeasurePath(&e, meter, options.clearance_samples, ShowProgress("measuring the " + e.key + " path"));
  }
  const PathEntry* shown = nullptr;
  for (const PathEntry& e : paths) {
    if (!e.artifact.waypoints.empty() && (shown == nullptr || e.key == "smoothed")) shown = &e;
  }
  const ShellNamer shell_names = [&namer](int shell, bool robot) { return namer.Shell(shell, robot); };
  const Headline headline = MakeHeadline(verdict ? &*verdict : nullptr, verdict_problem, shown, scene.units,
                                         parts ? shell_names : ShellNamer());

  // Geometry: S in world coordinates; D relative to the reference point, so
  // that float32 keeps D's detail however far its mesh origin is.
  const std::string static_json = MeshJson(scene.static_mesh, Eigen::Vector3d::Zero(), &store);
  const std::string dynamic_json = MeshJson(scene.dynamic_mesh, problem.reference_point, &store);

  std::string paths_json = "[";
  for (std::size_t i = 0; i < paths.size(); ++i) {
    paths_json += (i ? "," : "") + PathJson(paths[i], scene.units, namer, parts != nullptr,
                                            paths[i].key == "smoothed" && profile ? &*profile : nullptr);
  }
  paths_json += "]";
  const UpAxis up = SceneUpAxis(scene);
  const std::string data =
      "{\"format\":\"ausbau-report/2\",\"scene\":{\"name\":" + JsonString(scene.name) +
      ",\"units\":" + JsonString(scene.units) + ",\"length_unit\":" + JsonString(LengthUnit(scene.units)) +
      ",\"up\":{\"axis\":" + JsonString(up.axis) + ",\"source\":" + JsonString(up.source) + "}" +
      ",\"dynamic_origin\":" + JsonVector(scene.dynamic_origin) + ",\"start\":" + JsonPose(scene.start) +
      ",\"goal\":" + (scene.goal ? JsonPose(*scene.goal) : "null") + "},\"static\":" + static_json +
      ",\"dynamic\":" + dynamic_json + ",\"dynamic_shift\":" + JsonVector(problem.reference_point) +
      ",\"paths\":" + paths_json + ",\"labels\":" + labels_json + ",\"json_files\":" + json_files +
      ",\"headline\":{\"verdict\":" + JsonString(headline.verdict) + ",\"sentence\":" + JsonString(headline.sentence) +
      "},\"rigid_tolerance\":" + JsonNumber(parts ? tolerance : std::nan("")) + "}";

  return ReportPageHtml({options, assets, scene, problem, paths, artifacts, headline, data, store});
}

}  // namespace ausbau
