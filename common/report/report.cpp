#include "report/report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "artifact/artifact.h"
#include "collision/fcl_checker.h"
#include "core/error.h"
#include "core/format.h"
#include "core/log.h"
#include "labeling/pbd_label.h"
#include "planning/path_io.h"
#include "planning/scene_goal.h"
#include "planning/state_space.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- text utils

std::string ReadTextFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputErrorAt(file.string(), "cannot read file");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A JSON string literal that is also safe inside an HTML <script> element
// ("<" is escaped, so "</script>" cannot appear).
std::string JsonString(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '<': out += "\\u003c"; break;
      case '>': out += "\\u003e"; break;
      case '&': out += "\\u0026"; break;
      default:
        if (u < 0x20) {
          out += Fmt("\\u%04x", u);
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string JsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  return Fmt("%.17g", value);
}

std::string JsonNumbers(const double* values, std::size_t n) {
  std::string out = "[";
  for (std::size_t i = 0; i < n; ++i) out += (i ? "," : "") + JsonNumber(values[i]);
  return out + "]";
}

std::string JsonNumbers(const std::vector<double>& values) { return JsonNumbers(values.data(), values.size()); }

std::string JsonVector(const Eigen::Vector3d& v) { return JsonNumbers(v.data(), 3); }

std::string JsonPose(const Pose& pose) {
  return "{\"t\":" + JsonVector(pose.t) + ",\"q\":[" + JsonNumber(pose.q.w()) + "," + JsonNumber(pose.q.x()) + "," +
         JsonNumber(pose.q.y()) + "," + JsonNumber(pose.q.z()) + "]}";
}

std::string Num(double value) {
  if (!std::isfinite(value)) return "–";
  return Fmt("%.4g", value);
}

std::string Int(std::int64_t value) { return std::to_string(value); }

// ----------------------------------------------------------- binary buffers

// Little-endian bytes of float32 / uint32 arrays, whatever the host's order.
std::string Float32Bytes(const std::vector<float>& values) {
  std::string bytes(values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, &values[i], 4);
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<char>((bits >> (8 * k)) & 0xff);
  }
  return bytes;
}

std::string Uint32Bytes(const std::vector<std::uint32_t>& values) {
  std::string bytes(values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<char>((values[i] >> (8 * k)) & 0xff);
  }
  return bytes;
}

// Buffers embedded as <script type="application/octet-stream"> elements.
class BufferStore {
 public:
  // Returns the JSON reference {"buffer": i, "type": ..., "count": n}.
  std::string Add(const std::string& bytes, const char* type, std::size_t count) {
    buffers_.push_back(Base64Encode(bytes.data(), bytes.size()));
    return Fmt("{\"buffer\":%zu,\"type\":\"%s\",\"count\":%zu}", buffers_.size() - 1, type, count);
  }
  std::string Html() const {
    std::string out;
    for (std::size_t i = 0; i < buffers_.size(); ++i) {
      out += Fmt("<script type=\"application/octet-stream\" id=\"ausbau-buf-%zu\">", i);
      out += buffers_[i];
      out += "</script>\n";
    }
    return out;
  }

 private:
  std::vector<std::string> buffers_;
};

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

// ------------------------------------------------------------------- paths

struct PathEntry {
  std::string key;  // "planned" / "smoothed"
  fs::path file;
  PathArtifact artifact;
  std::string producer;
  std::optional<double> length_translation, length_rotation;
  std::vector<double> times;               // animation time of each waypoint, 0 .. 1
  std::vector<double> waypoint_clearance;  // FCL distance at each waypoint
  std::vector<double> sample_times;        // dense samples
  std::vector<double> sample_clearance;
};

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

void ComputeClearance(PathEntry* entry, const PlanningProblem& problem, const FclCollisionChecker& checker,
                      int samples) {
  const PathArtifact& path = entry->artifact;
  if (path.waypoints.empty()) return;
  for (const Pose& pose : path.waypoints) {
    entry->waypoint_clearance.push_back(checker.Distance(problem.SceneToPlanning(pose)));
  }
  if (path.waypoints.size() < 2 || samples <= 0) return;
  for (int k = 0; k <= samples; ++k) {
    const double u = static_cast<double>(k) / samples;
    entry->sample_times.push_back(u);
    entry->sample_clearance.push_back(checker.Distance(problem.SceneToPlanning(PoseAtTime(path, entry->times, u))));
  }
}

double MinOf(const std::vector<double>& values) {
  double m = std::numeric_limits<double>::infinity();
  for (double v : values) m = std::min(m, v);
  return m;
}

std::string PathJson(const PathEntry& e) {
  const PathArtifact& p = e.artifact;
  std::string wp = "[";
  for (std::size_t i = 0; i < p.waypoints.size(); ++i) wp += (i ? "," : "") + JsonPose(p.waypoints[i]);
  wp += "]";
  std::string series = "[";
  if (!e.waypoint_clearance.empty()) {
    series += "{\"name\":\"clearance\",\"label\":\"clearance (FCL distance between D and S)\",\"x\":" +
              JsonNumbers(e.sample_times) + ",\"y\":" + JsonNumbers(e.sample_clearance) +
              ",\"waypoints\":" + JsonNumbers(e.waypoint_clearance) + "}";
  }
  series += "]";
  return "{\"key\":" + JsonString(e.key) + ",\"file\":" + JsonString(e.file.string()) +
         ",\"success\":" + (p.success ? "true" : "false") + ",\"reference_point\":" + JsonVector(p.reference_point) +
         ",\"dynamic_origin\":" + JsonVector(p.dynamic_origin) + ",\"waypoints\":" + wp +
         ",\"times\":" + JsonNumbers(e.times) + ",\"series\":" + series + "}";
}

// ------------------------------------------------------------------- tables

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // cells are HTML already
};

std::string TableHtml(const Table& table, const std::string& id) {
  std::string out = "<table id=\"" + id + "\"><thead><tr>";
  for (const auto& h : table.header) out += "<th>" + h + "</th>";
  out += "</tr></thead><tbody>\n";
  for (const auto& row : table.rows) {
    out += "<tr>";
    for (std::size_t i = 0; i < row.size(); ++i)
      out += (i == 0 ? "<th>" : "<td>") + row[i] + (i == 0 ? "</th>" : "</td>");
    out += "</tr>\n";
  }
  return out + "</tbody></table>\n";
}

std::string StatsTable(const std::vector<PathEntry>& paths) {
  Table t;
  t.header.push_back("");
  for (const auto& e : paths)
    t.header.push_back(HtmlEscape(e.key) + "<br><code>" + HtmlEscape(e.file.string()) + "</code>");
  auto row = [&](const std::string& name, auto cell) {
    std::vector<std::string> r{name};
    for (const auto& e : paths) r.push_back(cell(e));
    t.rows.push_back(r);
  };
  row("producer", [](const PathEntry& e) { return HtmlEscape(e.producer); });
  row("planner", [](const PathEntry& e) { return HtmlEscape(e.artifact.planner); });
  row("success", [](const PathEntry& e) { return std::string(e.artifact.success ? "yes" : "<b>no</b>"); });
  row("waypoints", [](const PathEntry& e) { return Int(e.artifact.waypoints.size()); });
  row("planning time (s)", [](const PathEntry& e) { return Num(e.artifact.stats.time_s); });
  row("iterations", [](const PathEntry& e) { return Int(e.artifact.stats.iterations); });
  row("nodes", [](const PathEntry& e) { return Int(e.artifact.stats.nodes); });
  row("collision checks", [](const PathEntry& e) { return Int(e.artifact.stats.collision_checks); });
  row("invalid checks", [](const PathEntry& e) {
    const auto& s = e.artifact.stats;
    return Int(s.invalid_checks) +
           (s.collision_checks > 0 ? Fmt(" (%.1f%%)", 100.0 * s.invalid_checks / s.collision_checks) : std::string());
  });
  row("length (normalized)", [](const PathEntry& e) { return Num(e.artifact.length_normalized); });
  row("length, translation",
      [](const PathEntry& e) { return e.length_translation ? Num(*e.length_translation) : "–"; });
  row("length, rotation (rad)", [](const PathEntry& e) { return e.length_rotation ? Num(*e.length_rotation) : "–"; });
  row("min clearance at waypoints", [](const PathEntry& e) {
    return e.waypoint_clearance.empty() ? std::string("–") : Num(MinOf(e.waypoint_clearance));
  });
  row("min clearance along the path", [](const PathEntry& e) {
    return e.sample_clearance.empty()
               ? std::string("–")
               : Num(std::min(MinOf(e.sample_clearance), MinOf(e.waypoint_clearance))) +
                     Fmt(" (%zu poses)", e.sample_clearance.size() + e.waypoint_clearance.size());
  });
  return TableHtml(t, "stats");
}

std::string PoseText(const Pose& p) {
  return Fmt("t = [%.6g, %.6g, %.6g], q = [%.6g, %.6g, %.6g, %.6g]", p.t.x(), p.t.y(), p.t.z(), p.q.w(), p.q.x(),
             p.q.y(), p.q.z());
}

std::string VectorText(const Eigen::Vector3d& v) { return Fmt("[%.6g, %.6g, %.6g]", v.x(), v.y(), v.z()); }

std::string SceneTable(const Scene& scene, const PlanningProblem& problem) {
  Table t;
  t.header = {"scene", HtmlEscape(scene.name)};
  auto row = [&](const std::string& k, const std::string& v) { t.rows.push_back({k, v}); };
  row("file", "<code>" + HtmlEscape(scene.file.string()) + "</code>");
  if (!scene.units.empty()) row("units", HtmlEscape(scene.units));
  std::string statics;
  for (const auto& f : scene.static_files)
    statics += (statics.empty() ? "" : ", ") + ("<code>" + HtmlEscape(f.string()) + "</code>");
  row("S (static)", statics + Fmt(": %zu triangles, %zu vertices", scene.static_mesh.triangles.size(),
                                  scene.static_mesh.vertices.size()));
  row("D (dynamic)", "<code>" + HtmlEscape(scene.dynamic_file.string()) + "</code>" +
                         Fmt(": %zu triangles, %zu vertices", scene.dynamic_mesh.triangles.size(),
                             scene.dynamic_mesh.vertices.size()));
  row("dynamic_origin", VectorText(scene.dynamic_origin) + (scene.dynamic_origin_given ? "" : " (default)"));
  row("reference point", VectorText(problem.reference_point));
  row("start", PoseText(scene.start));
  row("goal", scene.goal             ? PoseText(*scene.goal)
              : scene.goal_condition ? HtmlEscape(SceneGoal(scene).Describe())
                                     : std::string("none (disassembly: out of S's bounding box)"));
  row("bounds on t", VectorText(problem.bounds.min) + " .. " + VectorText(problem.bounds.max) +
                         (problem.bounds_given ? "" : " (derived)"));
  return TableHtml(t, "scene");
}

// -------------------------------------------------------------- HTML shell

const char kStyle[] = R"CSS(
* { box-sizing: border-box; }
body { margin: 0; font: 14px/1.4 system-ui, -apple-system, "Segoe UI", sans-serif; color: #1d232b; background: #fafbfc; }
header { padding: 10px 18px; background: #24303e; color: #f2f4f7; }
header h1 { margin: 0; font-size: 19px; font-weight: 600; }
header p { margin: 2px 0 0; font-size: 12px; color: #b8c2cf; }
main { padding: 12px 18px 30px; max-width: 1500px; }
#view { position: relative; height: 62vh; min-height: 320px; background: #eef1f5; border: 1px solid #cfd6df; border-radius: 4px; overflow: hidden; }
#canvas3d { display: block; width: 100%; height: 100%; }
#status { position: absolute; left: 10px; top: 8px; font-size: 12px; color: #3c4855; background: rgba(255,255,255,.75); padding: 2px 6px; border-radius: 3px; }
#legend { position: absolute; right: 10px; top: 8px; font-size: 12px; background: rgba(255,255,255,.85); padding: 4px 8px; border-radius: 3px; display: none; }
#legend .bar { width: 160px; height: 10px; margin: 3px 0; }
#help { position: absolute; left: 10px; bottom: 6px; font-size: 11px; color: #5b6773; }
#controls { display: flex; flex-wrap: wrap; gap: 8px 14px; align-items: center; padding: 8px 0; }
#controls button { min-width: 70px; padding: 4px 10px; font-size: 14px; }
#scrubber { flex: 1 1 320px; }
#controls label { font-size: 13px; white-space: nowrap; }
#timeinfo { font-variant-numeric: tabular-nums; font-size: 13px; min-width: 200px; }
#plotbox { position: relative; border: 1px solid #cfd6df; border-radius: 4px; background: #fff; }
#plot { display: block; width: 100%; height: 190px; cursor: crosshair; }
#plotnote { font-size: 12px; color: #5b6773; margin: 4px 0 0; }
h2 { font-size: 16px; margin: 22px 0 8px; }
table { border-collapse: collapse; margin: 4px 0 10px; font-size: 13px; background: #fff; }
th, td { border: 1px solid #d5dbe3; padding: 3px 9px; text-align: left; vertical-align: top; }
thead th { background: #eef1f5; }
tbody th { font-weight: 500; background: #f7f8fa; }
td { font-variant-numeric: tabular-nums; }
code { font-size: 12px; }
.note { color: #7a4b00; }
.grid { display: flex; flex-wrap: wrap; gap: 0 28px; }
)CSS";

// Makes inline module code safe inside <script> (it must not close it).
std::string ScriptSafe(std::string_view code) {
  std::string out(code);
  for (std::size_t at = 0; (at = out.find("</script", at)) != std::string::npos; at += 2) out.replace(at, 2, "<\\/");
  return out;
}

std::string ImportMap(const ReportAssets& assets) {
  const std::string three = Base64Encode(assets.three_module.data(), assets.three_module.size());
  const std::string orbit = Base64Encode(assets.orbit_controls.data(), assets.orbit_controls.size());
  return "<script type=\"importmap\">{\"imports\":{\"three\":\"data:text/javascript;base64," + three +
         "\",\"three/addons/controls/OrbitControls.js\":\"data:text/javascript;base64," + orbit + "\"}}</script>\n";
}

bool IsRegularFile(const fs::path& file) {
  std::error_code ec;
  return fs::is_regular_file(file, ec);
}

}  // namespace

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
      default: out += c;
    }
  }
  return out;
}

// ------------------------------------------------------------------ report

namespace {

// The files of a report: given one by one, or found by name in a run
// folder (the command line's files win). What a run folder lacks is noted
// in the summary and in `artifacts` (name, status as HTML).
struct ReportFiles {
  fs::path path_file, smoothed_file, labels_file, verdict_file, stats_file, spheres_file;
};

ReportFiles FindReportFiles(const ReportOptions& options, ReportSummary* summary,
                            std::vector<std::pair<std::string, std::string>>* artifacts_out) {
  std::vector<std::pair<std::string, std::string>>& artifacts = *artifacts_out;
  ReportFiles files;
  fs::path& path_file = files.path_file;
  fs::path& smoothed_file = files.smoothed_file;
  fs::path& labels_file = files.labels_file;
  fs::path& verdict_file = files.verdict_file;
  fs::path& stats_file = files.stats_file;
  fs::path& spheres_file = files.spheres_file;
  path_file = options.path;
  smoothed_file = options.smoothed;
  std::string absent;
  if (!options.run_dir.empty()) {
    std::error_code ec;
    if (!fs::is_directory(options.run_dir, ec)) throw InputErrorAt(options.run_dir.string(), "run folder not found");
    auto pick = [&](const char* name, fs::path* slot, bool explicit_given) {
      const fs::path candidate = options.run_dir / name;
      if (explicit_given) {
        artifacts.emplace_back(name, "replaced by the command line's file");
      } else if (IsRegularFile(candidate)) {
        *slot = candidate;
      } else {
        artifacts.emplace_back(name, "absent");
        absent += std::string(absent.empty() ? "" : ", ") + name;
      }
    };
    pick("path.h5", &path_file, !options.path.empty());
    pick("path-smooth.h5", &smoothed_file, !options.smoothed.empty());
    pick("labels.h5", &labels_file, false);
    pick("spheres.h5", &spheres_file, false);
    pick("verdict.json", &verdict_file, false);
    pick("stats.json", &stats_file, false);
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
      artifacts.emplace_back("labels.h5", "used: D coloured by deformability");
    } catch (const InputError& e) {
      LogWarn("labels ignored: %s", e.what());
      summary->notes.push_back(std::string("labels ignored: ") + e.what());
      artifacts.emplace_back("labels.h5", "<span class=\"note\">ignored: " + HtmlEscape(e.what()) + "</span>");
    }
  }
  return labels_json;
}

}  // namespace

// The planned and smoothed paths of the run, checked to belong to `scene`,
// with their animation times and clearance along them.
std::vector<PathEntry> LoadReportPaths(const ReportFiles& files, const Scene& scene, const PlanningProblem& problem,
                                       int clearance_samples, ReportSummary* summary,
                                       std::vector<std::pair<std::string, std::string>>* artifacts) {
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
    summary->used.push_back(e.key + " path: " + e.file.string());
    artifacts->emplace_back(e.file.filename().string(), "used: " + e.key + " path");
  }
  if (!paths.empty()) {
    const FclCollisionChecker checker(problem.robot, problem.environment);
    for (PathEntry& e : paths) ComputeClearance(&e, problem, checker, clearance_samples);
  }
  return paths;
}

// verdict.json and stats.json as they are, for the page's tables; an
// unreadable one is noted and left out.
std::string JsonFilesJson(const ReportFiles& files, ReportSummary* summary,
                          std::vector<std::pair<std::string, std::string>>* artifacts) {
  std::string json_files = "[";
  for (const auto& [name, file] :
       {std::pair<std::string, fs::path>{"verdict", files.verdict_file}, {"stats", files.stats_file}}) {
    if (file.empty()) continue;
    std::string text;
    try {
      text = ReadTextFile(file);
    } catch (const InputError& e) {
      summary->notes.push_back(e.what());
      artifacts->emplace_back(file.filename().string(),
                              "<span class=\"note\">ignored: " + HtmlEscape(e.what()) + "</span>");
      continue;
    }
    json_files += (json_files.size() > 1 ? "," : "") +
                  ("{\"name\":" + JsonString(name) + ",\"file\":" + JsonString(file.string()) +
                   ",\"text\":" + JsonString(text) + "}");
    summary->used.push_back(name + ": " + file.string());
    artifacts->emplace_back(file.filename().string(), "used: shown as a table");
  }
  return json_files + "]";
}

// What the page shows, as the page: header, 3D view and its controls, the
// plot, the tables; `data` is the JSON the viewer script reads.
std::string ReportPageHtml(const ReportOptions& options, const ReportAssets& assets, const Scene& scene,
                           const PlanningProblem& problem, const std::vector<PathEntry>& paths,
                           const std::vector<std::pair<std::string, std::string>>& artifacts, const std::string& data,
                           const BufferStore& store) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<meta name=\"generator\" content=\"ausbau-report " << AUSBAU_VERSION << ", three.js "
       << HtmlEscape(assets.three_version) << "\">\n"
       << "<title>Ausbau report: " << HtmlEscape(scene.name) << "</title>\n<style>" << kStyle << "</style>\n"
       << ImportMap(assets) << "</head>\n<body>\n";
  html << "<header><h1>Ausbau report: " << HtmlEscape(scene.name) << "</h1><p>S " << scene.static_mesh.triangles.size()
       << " triangles, D " << scene.dynamic_mesh.triangles.size() << " triangles";
  for (const auto& e : paths)
    html << "; " << HtmlEscape(e.key) << " path: " << e.artifact.waypoints.size() << " waypoints";
  html << ". Written by ausbau-report " << AUSBAU_VERSION << " (three.js " << HtmlEscape(assets.three_version)
       << ", inlined; works offline).</p></header>\n<main>\n";
  html << "<div id=\"view\"><canvas id=\"canvas3d\"></canvas><div id=\"status\">loading…</div>"
          "<div id=\"legend\"></div><div id=\"help\">drag: orbit · right-drag: pan · wheel: zoom · space: play/pause"
          " · D orange, S blue, line: path of D's reference point</div></div>\n";
  html << "<div id=\"controls\">"
          "<button id=\"play\" type=\"button\">Play</button>"
          "<input id=\"scrubber\" type=\"range\" min=\"0\" max=\"1000\" step=\"1\" value=\"0\" aria-label=\"path "
          "position\">"
          "<span id=\"timeinfo\"></span>"
          "<label>speed <select id=\"speed\"><option value=\"0.25\">0.25×</option><option value=\"0.5\">0.5×</option>"
          "<option value=\"1\" selected>1×</option><option value=\"2\">2×</option><option value=\"4\">4×</option>"
          "</select></label>"
          "<label>path <select id=\"pathselect\"></select></label>"
          "<label>S opacity <input id=\"opacity\" type=\"range\" min=\"0\" max=\"1\" step=\"0.05\" "
          "value=\"0.35\"></label>"
          "<label><input id=\"showtrace\" type=\"checkbox\" checked> path line</label>"
          "<label><input id=\"showghosts\" type=\"checkbox\"> start/goal ghosts</label>"
          "</div>\n";
  html << "<div id=\"plotbox\"><canvas id=\"plot\"></canvas></div><p id=\"plotnote\"></p>\n";
  html << "<div class=\"grid\"><div><h2>Path statistics</h2>";
  if (paths.empty()) {
    html << "<p class=\"note\">No path given: the page shows the scene only.</p>";
  } else {
    html << StatsTable(paths);
  }
  html << "</div><div><h2>Scene</h2>" << SceneTable(scene, problem) << "</div></div>\n";
  html << "<div id=\"jsontables\"></div>\n";
  if (!options.run_dir.empty()) {
    Table t;
    t.header = {"file", "status"};
    for (const auto& [name, status] : artifacts) t.rows.push_back({"<code>" + HtmlEscape(name) + "</code>", status});
    html << "<h2>Run folder <code>" << HtmlEscape(options.run_dir.string()) << "</code></h2>"
         << TableHtml(t, "artifacts");
  }
  html << "</main>\n";
  html << "<script type=\"application/json\" id=\"ausbau-data\">" << data << "</script>\n";
  html << store.Html();
  html << "<script type=\"module\">\n" << ScriptSafe(assets.viewer) << "\n</script>\n</body>\n</html>\n";
  return html.str();
}

std::string BuildReportHtml(const ReportOptions& options, const ReportAssets& assets, ReportSummary* summary) {
  ReportSummary local;
  if (!summary) summary = &local;
  if (options.scene.empty()) throw InputError("--scene is required");
  std::vector<std::pair<std::string, std::string>> artifacts;  // name, status (HTML)
  const ReportFiles files = FindReportFiles(options, summary, &artifacts);

  const Scene scene = LoadScene(options.scene);
  const PlanningProblem problem = MakePlanningProblem(scene);
  summary->used.push_back("scene: " + options.scene.string());
  const std::vector<PathEntry> paths =
      LoadReportPaths(files, scene, problem, options.clearance_samples, summary, &artifacts);

  BufferStore store;
  const std::string labels_json = LabelsJson(files.labels_file, scene, &store, summary, &artifacts);
  if (!files.spheres_file.empty()) artifacts.emplace_back("spheres.h5", "present (not shown by this version)");
  const std::string json_files = JsonFilesJson(files, summary, &artifacts);

  // Geometry: S in world coordinates; D relative to the reference point, so
  // that float32 keeps D's detail however far its mesh origin is.
  const std::string static_json = MeshJson(scene.static_mesh, Eigen::Vector3d::Zero(), &store);
  const std::string dynamic_json = MeshJson(scene.dynamic_mesh, problem.reference_point, &store);

  std::string paths_json = "[";
  for (std::size_t i = 0; i < paths.size(); ++i) paths_json += (i ? "," : "") + PathJson(paths[i]);
  paths_json += "]";
  const std::string data =
      "{\"format\":\"ausbau-report/1\",\"scene\":{\"name\":" + JsonString(scene.name) +
      ",\"units\":" + JsonString(scene.units) + ",\"dynamic_origin\":" + JsonVector(scene.dynamic_origin) +
      ",\"start\":" + JsonPose(scene.start) + ",\"goal\":" + (scene.goal ? JsonPose(*scene.goal) : "null") +
      "},\"static\":" + static_json + ",\"dynamic\":" + dynamic_json +
      ",\"dynamic_shift\":" + JsonVector(problem.reference_point) + ",\"paths\":" + paths_json +
      ",\"labels\":" + labels_json + ",\"json_files\":" + json_files + "}";

  return ReportPageHtml(options, assets, scene, problem, paths, artifacts, data, store);
}

// -------------------------------------------------------------- markdown

namespace {

std::string InlineMarkdown(const std::string& text) {
  std::string out;
  bool bold = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\\' && i + 1 < text.size() && std::strchr("\\`*_|#-", text[i + 1])) {
      out += HtmlEscape(std::string(1, text[++i]));
    } else if (c == '`') {
      const std::size_t end = text.find('`', i + 1);
      if (end == std::string::npos) {
        out += "`";
        continue;
      }
      out += "<code>" + HtmlEscape(text.substr(i + 1, end - i - 1)) + "</code>";
      i = end;
    } else if (c == '*' && i + 1 < text.size() && text[i + 1] == '*') {
      out += bold ? "</b>" : "<b>";
      bold = !bold;
      ++i;
    } else {
      out += HtmlEscape(std::string(1, c));
    }
  }
  if (bold) out += "</b>";
  return out;
}

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// Splits "| a | b |" into cells, honouring "\|".
std::vector<std::string> TableCells(const std::string& line) {
  std::string s = Trim(line);
  if (!s.empty() && s.front() == '|') s.erase(0, 1);
  if (!s.empty() && s.back() == '|' && (s.size() < 2 || s[s.size() - 2] != '\\')) s.pop_back();
  std::vector<std::string> cells;
  std::string cell;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size() && s[i + 1] == '|') {
      cell += "\\|";
      ++i;
    } else if (s[i] == '|') {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += s[i];
    }
  }
  cells.push_back(Trim(cell));
  return cells;
}

bool IsAlignmentRow(const std::string& line) {
  const std::string s = Trim(line);
  if (s.empty() || s.find('-') == std::string::npos) return false;
  return s.find_first_not_of("|-: ") == std::string::npos;
}

// "- x" / "* x" / "1. x": the list kind ('u' or 'o'), the indent and the text.
bool ListItem(const std::string& line, char* kind, std::size_t* indent, std::string* text) {
  const std::size_t b = line.find_first_not_of(' ');
  if (b == std::string::npos) return false;
  if ((line[b] == '-' || line[b] == '*') && b + 1 < line.size() && line[b + 1] == ' ') {
    *kind = 'u';
    *indent = b;
    *text = line.substr(b + 2);
    return true;
  }
  std::size_t d = b;
  while (d < line.size() && std::isdigit(static_cast<unsigned char>(line[d]))) ++d;
  if (d > b && d + 1 < line.size() && line[d] == '.' && line[d + 1] == ' ') {
    *kind = 'o';
    *indent = b;
    *text = line.substr(d + 2);
    return true;
  }
  return false;
}

}  // namespace

std::string MarkdownToHtml(const std::string& markdown) {
  std::vector<std::string> lines;
  {
    std::istringstream in(markdown);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines.push_back(line);
    }
  }
  std::string out;
  std::size_t i = 0;
  while (i < lines.size()) {
    const std::string& line = lines[i];
    const std::string trimmed = Trim(line);
    char kind;
    std::size_t indent;
    std::string text;
    if (trimmed.empty()) {
      ++i;
    } else if (trimmed[0] == '#') {
      std::size_t level = trimmed.find_first_not_of('#');
      if (level == std::string::npos) level = trimmed.size();
      const std::size_t h = std::min<std::size_t>(level, 6);
      out += Fmt("<h%zu>", h) + InlineMarkdown(Trim(trimmed.substr(level))) + Fmt("</h%zu>\n", h);
      ++i;
    } else if (trimmed[0] == '|' && i + 1 < lines.size() && IsAlignmentRow(lines[i + 1])) {
      const std::vector<std::string> header = TableCells(line);
      const std::vector<std::string> align = TableCells(lines[i + 1]);
      auto style = [&](std::size_t c) -> std::string {
        if (c >= align.size()) return "";
        const std::string& a = align[c];
        if (a.size() > 1 && a.back() == ':' && a.front() == ':') return " style=\"text-align:center\"";
        if (!a.empty() && a.back() == ':') return " style=\"text-align:right\"";
        return "";
      };
      out += "<table><thead><tr>";
      for (std::size_t c = 0; c < header.size(); ++c)
        out += "<th" + style(c) + ">" + InlineMarkdown(header[c]) + "</th>";
      out += "</tr></thead><tbody>\n";
      i += 2;
      while (i < lines.size() && !Trim(lines[i]).empty() && Trim(lines[i])[0] == '|') {
        const std::vector<std::string> cells = TableCells(lines[i]);
        out += "<tr>";
        for (std::size_t c = 0; c < cells.size(); ++c)
          out += "<td" + style(c) + ">" + InlineMarkdown(cells[c]) + "</td>";
        out += "</tr>\n";
        ++i;
      }
      out += "</tbody></table>\n";
    } else if (ListItem(line, &kind, &indent, &text)) {
      // A list with nested items (deeper indent) as sub-lists.
      std::vector<std::pair<char, std::size_t>> open;  // kind, indent
      bool item_open = false;
      while (i < lines.size() && ListItem(lines[i], &kind, &indent, &text)) {
        while (!open.empty() && indent < open.back().second) {
          out += "</li>";
          out += open.back().first == 'u' ? "</ul>" : "</ol>";
          open.pop_back();
        }
        if (open.empty() || indent > open.back().second) {
          out += kind == 'u' ? "<ul>" : "<ol>";
          open.emplace_back(kind, indent);
          item_open = false;
        }
        if (item_open) out += "</li>\n";
        out += "<li>" + InlineMarkdown(text);
        item_open = true;
        ++i;
        // Continuation lines (indented, not a new item).
        while (i < lines.size() && !Trim(lines[i]).empty() && lines[i][0] == ' ' &&
               !ListItem(lines[i], &kind, &indent, &text)) {
          out += " " + InlineMarkdown(Trim(lines[i]));
          ++i;
        }
      }
      while (!open.empty()) {
        out += "</li>";
        out += open.back().first == 'u' ? "</ul>" : "</ol>";
        open.pop_back();
      }
      out += "\n";
    } else {
      std::string paragraph = InlineMarkdown(trimmed);
      ++i;
      while (i < lines.size() && !Trim(lines[i]).empty() && Trim(lines[i])[0] != '#' && Trim(lines[i])[0] != '|' &&
             !ListItem(lines[i], &kind, &indent, &text)) {
        paragraph += " " + InlineMarkdown(Trim(lines[i]));
        ++i;
      }
      out += "<p>" + paragraph + "</p>\n";
    }
  }
  return out;
}

// -------------------------------------------------------------- bench page

namespace {

struct BenchRow {
  std::string scene, planner;
  bool success = false;
  double time_s = 0;
};

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (char c : line) {
    if (c == ',') {
      cells.push_back(cell);
      cell.clear();
    } else if (c != '\r') {
      cell += c;
    }
  }
  cells.push_back(cell);
  return cells;
}

// results.csv of ausbau-bench: scene,planner,seed,success,time_s,...
std::vector<BenchRow> ReadResultsCsv(const fs::path& file, std::string* problem) {
  std::istringstream in(ReadTextFile(file));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = SplitCsvLine(line);
  auto column = [&](const char* name) -> int {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  const int scene = column("scene"), planner = column("planner"), success = column("success"), time = column("time_s");
  std::vector<BenchRow> rows;
  if (scene < 0 || planner < 0 || success < 0 || time < 0) {
    *problem = "expected the columns scene, planner, success, time_s";
    return rows;
  }
  while (std::getline(in, line)) {
    if (Trim(line).empty()) continue;
    const std::vector<std::string> cells = SplitCsvLine(line);
    if (cells.size() < header.size()) continue;
    BenchRow row;
    row.scene = cells[scene];
    row.planner = cells[planner];
    row.success = cells[success] == "1";
    try {
      row.time_s = std::stod(cells[time]);
    } catch (const std::exception&) {
      continue;
    }
    rows.push_back(row);
  }
  return rows;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string BarChartSvg(const std::string& scene, const std::vector<BenchRow>& rows) {
  std::vector<std::string> planners;
  for (const BenchRow& r : rows) {
    if (r.scene == scene && std::find(planners.begin(), planners.end(), r.planner) == planners.end()) {
      planners.push_back(r.planner);
    }
  }
  struct Bar {
    std::string planner;
    double median;
    int successes, runs;
  };
  std::vector<Bar> bars;
  double top = 0;
  for (const std::string& p : planners) {
    std::vector<double> times;
    int successes = 0;
    for (const BenchRow& r : rows) {
      if (r.scene != scene || r.planner != p) continue;
      times.push_back(r.time_s);
      successes += r.success;
    }
    bars.push_back({p, Median(times), successes, static_cast<int>(times.size())});
    top = std::max(top, bars.back().median);
  }
  const int label_w = 170, bar_w = 420, row_h = 24, width = label_w + bar_w + 190;
  const int height = 30 + row_h * static_cast<int>(bars.size()) + 10;
  std::string svg =
      Fmt("<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"bars\" width=\"%d\" height=\"%d\" "
          "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\" font-size=\"12\">",
          width, height, width, height);
  svg += Fmt("<text x=\"0\" y=\"16\" font-weight=\"bold\">%s: median time (s)</text>", HtmlEscape(scene).c_str());
  for (std::size_t k = 0; k < bars.size(); ++k) {
    const Bar& b = bars[k];
    const int y = 30 + static_cast<int>(k) * row_h;
    const double w = top > 0 ? bar_w * b.median / top : 0;
    const char* colour = b.successes == b.runs ? "#4c9a5b" : b.successes == 0 ? "#c8553d" : "#e0a030";
    svg += Fmt("<text x=\"%d\" y=\"%d\" text-anchor=\"end\">%s</text>", label_w - 8, y + 15,
               HtmlEscape(b.planner).c_str());
    svg +=
        Fmt("<rect x=\"%d\" y=\"%d\" width=\"%.1f\" height=\"%d\" fill=\"%s\"><title>%s: median %s s, %d/%d "
            "solved</title></rect>",
            label_w, y + 3, std::max(w, 1.0), row_h - 6, colour, HtmlEscape(b.planner).c_str(), Num(b.median).c_str(),
            b.successes, b.runs);
    svg += Fmt("<text x=\"%.1f\" y=\"%d\">%s s (%d/%d solved)</text>", label_w + std::max(w, 1.0) + 6, y + 15,
               Num(b.median).c_str(), b.successes, b.runs);
  }
  return svg + "</svg>";
}

}  // namespace

std::string BuildBenchPageHtml(const fs::path& bench_dir, ReportSummary* summary) {
  ReportSummary local;
  if (!summary) summary = &local;
  std::error_code ec;
  if (!fs::is_directory(bench_dir, ec)) throw InputErrorAt(bench_dir.string(), "benchmark folder not found");
  std::vector<fs::path> svgs;
  for (const auto& entry : fs::directory_iterator(bench_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("study-", 0) == 0 && entry.path().extension() == ".svg") svgs.push_back(entry.path());
  }
  std::sort(svgs.begin(), svgs.end());
  const fs::path summary_md = bench_dir / "summary.md", study_md = bench_dir / "study-summary.md",
                 results = bench_dir / "results.csv";
  if (!IsRegularFile(summary_md) && !IsRegularFile(study_md) && !IsRegularFile(results) && svgs.empty()) {
    throw InputErrorAt(bench_dir.string(),
                       "no benchmark outputs (summary.md, study-summary.md, results.csv or study-*.svg)");
  }
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<title>Ausbau benchmarks: " << HtmlEscape(bench_dir.string()) << "</title>\n<style>" << kStyle
       << "main h1 { font-size: 20px; } main h2 { font-size: 17px; border-bottom: 1px solid #d5dbe3; }"
          " svg { max-width: 100%; height: auto; display: block; margin: 6px 0 14px; }"
          "</style>\n</head>\n<body>\n<header><h1>Ausbau benchmarks</h1><p>from <code>"
       << HtmlEscape(bench_dir.string()) << "</code>, written by ausbau-report " << AUSBAU_VERSION
       << "</p></header>\n<main>\n";
  if (IsRegularFile(results)) {
    std::string problem;
    const std::vector<BenchRow> rows = ReadResultsCsv(results, &problem);
    html << "<section id=\"bars\"><h1>Median planning time per scene</h1>";
    if (!problem.empty()) {
      html << "<p class=\"note\">results.csv: " << HtmlEscape(problem) << "</p>";
      summary->notes.push_back(results.string() + ": " + problem);
    } else {
      html << "<p>From <code>results.csv</code> (" << rows.size()
           << " runs): the median over all runs, failed runs with their recorded time (about the time limit);"
              " green = all solved, amber = some, red = none.</p>";
      std::vector<std::string> scenes;
      for (const BenchRow& r : rows) {
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
      }
      for (const std::string& s : scenes) html << BarChartSvg(s, rows) << "\n";
    }
    html << "</section>\n";
    summary->used.push_back("results: " + results.string());
  }
  for (const fs::path& md : {summary_md, study_md}) {
    if (!IsRegularFile(md)) continue;
    html << "<section class=\"markdown\">" << MarkdownToHtml(ReadTextFile(md)) << "</section>\n";
    summary->used.push_back("markdown: " + md.string());
  }
  if (!svgs.empty()) html << "<section id=\"heatmaps\"><h1>Parameter study heat maps</h1>\n";
  for (const fs::path& svg_file : svgs) {
    std::string svg = ReadTextFile(svg_file);
    if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find("?>") + 2);
    const std::size_t at = svg.find("<svg");
    if (at == std::string::npos) {
      summary->notes.push_back(svg_file.string() + ": not an SVG, skipped");
      continue;
    }
    html << "<h2>" << HtmlEscape(svg_file.filename().string()) << "</h2>\n" << svg.substr(at) << "\n";
    summary->used.push_back("heat map: " + svg_file.string());
  }
  if (!svgs.empty()) html << "</section>\n";
  html << "</main>\n</body>\n</html>\n";
  return html.str();
}

}  // namespace ausbau
