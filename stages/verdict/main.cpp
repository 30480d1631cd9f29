// ausbau-verdict: the answer of an InIState run for one scene - is D
// removable, where along the path is the largest (Labeled-)MLIV, how long did
// the stages take - as verdict.json (schemas/verdict.md) and a short summary
// on stdout. See README.md beside this file.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "artifact/artifact.h"
#include "cli/stage_main.h"
#include "core/atomic_file.h"
#include "core/log.h"
#include "inistate/tau_estimate.h"
#include "planning/exact_check.h"
#include "planning/path_io.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

inline constexpr char kVerdictSchema[] = "ausbau-verdict";
inline constexpr int kVerdictSchemaVersion = 1;

struct VerdictOptions {
  std::string scene;
  std::string path;
  std::string tau;
  std::string times;
  std::string csv_name;
  double budget = -1;  // < 0: none
  double rigid_tolerance_mm = 0.05;
  std::string output = "verdict.json";
};

// ---- a small JSON writer (no JSON library is a dependency of the project)

std::string JsonEscape(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buffer;
        } else {
          out += c;  // UTF-8 passes through unchanged
        }
    }
  }
  return out + "\"";
}

std::string JsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::string JsonBool(bool value) { return value ? "true" : "false"; }

// An object built member by member; nested objects are passed as their text.
class JsonObject {
 public:
  JsonObject& Add(const std::string& key, const std::string& raw_value) {
    members_.emplace_back(key, raw_value);
    return *this;
  }
  JsonObject& String(const std::string& key, const std::string& value) { return Add(key, JsonEscape(value)); }
  JsonObject& Number(const std::string& key, double value) { return Add(key, JsonNumber(value)); }
  JsonObject& Int(const std::string& key, long long value) { return Add(key, std::to_string(value)); }
  JsonObject& Bool(const std::string& key, bool value) { return Add(key, JsonBool(value)); }
  JsonObject& Null(const std::string& key) { return Add(key, "null"); }

  // One member per line, two spaces of indentation per level.
  std::string Text() const {
    if (members_.empty()) return "{}";
    const std::string pad = "  ";
    std::string out = "{\n";
    for (std::size_t i = 0; i < members_.size(); ++i) {
      out += pad + JsonEscape(members_[i].first) + ": " + Indented(members_[i].second, pad);
      out += i + 1 < members_.size() ? ",\n" : "\n";
    }
    return out + "}";
  }

 private:
  // Nested objects' lines get the parent's indentation.
  static std::string Indented(const std::string& value, const std::string& pad) {
    std::string out;
    for (const char c : value) {
      out += c;
      if (c == '\n') out += pad;
    }
    return out;
  }
  std::vector<std::pair<std::string, std::string>> members_;
};

// ---- inputs

// Seconds per stage from DIR/<stage>.seconds (one number each, written by
// scripts/timed.sh), in pipeline order, then any others by name.
std::vector<std::pair<std::string, double>> ReadStageSeconds(const fs::path& dir) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) throw InputErrorAt(dir.string(), "--times: not a folder");
  std::map<std::string, double> found;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".seconds") continue;
    std::ifstream in(entry.path());
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::istringstream fields(text);
    double seconds = 0;
    std::string rest;
    if (!(fields >> seconds) || (fields >> rest) || !std::isfinite(seconds) || seconds < 0) {
      throw InputErrorAt(entry.path().string(), "expected one non-negative number of seconds");
    }
    found[entry.path().stem().string()] = seconds;
  }
  static const char* const kOrder[] = {"scene-gen",     "voxelize", "medial-spheres", "pbd-label", "distfield-build",
                                       "tau-estimate",  "plan",     "smooth",         "verdict",   "report"};
  std::vector<std::pair<std::string, double>> ordered;
  for (const char* stage : kOrder) {
    const auto it = found.find(stage);
    if (it == found.end()) continue;
    ordered.emplace_back(*it);
    found.erase(it);
  }
  for (const auto& entry : found) ordered.push_back(entry);
  return ordered;
}

// The translational and rotational lengths are informational datasets that
// ReadPathArtifact leaves out; read them when present.
void ReadLengthParts(const fs::path& file, double* translation, double* rotation) {
  const ArtifactReader reader(file, kPathSchema, kPathSchemaVersion);
  auto scalar = [&reader](const char* name) {
    if (!reader.Has(name)) return std::nan("");
    const Array<double> a = reader.ReadDoubles(name);
    return a.data.size() == 1 ? a.data[0] : std::nan("");
  };
  *translation = scalar("stats/length_translation");
  *rotation = scalar("stats/length_rotation");
}

struct MaxVolume {
  double value = 0;
  int index = 0;
  int part = -1;
  double deformability = 0;
  bool in_sigma_1 = false;
};

// The waypoint with the largest volume (the first of equals).
std::optional<MaxVolume> FindMaxVolume(const PathArtifact& path) {
  if (path.waypoint_volume.empty()) return std::nullopt;
  const auto it = std::max_element(path.waypoint_volume.begin(), path.waypoint_volume.end());
  MaxVolume max;
  max.index = static_cast<int>(it - path.waypoint_volume.begin());
  max.value = *it;
  max.part = path.waypoint_part[max.index];
  max.deformability = path.waypoint_deformability[max.index];
  max.in_sigma_1 = path.inter_index >= 0 && max.index <= path.inter_index;
  return max;
}

int Run(const VerdictOptions& options) {
  if (!std::isfinite(options.budget)) throw InputError("--budget: must be a finite number");
  const Scene scene = LoadScene(options.scene);
  const PathArtifact path = ReadPathArtifact(options.path);
  if (!path.scene.empty() && path.scene != scene.name) {
    throw InputErrorAt(options.path, "was planned for scene '" + path.scene + "', not '" + scene.name + "'");
  }
  double translation = 0, rotation = 0;
  ReadLengthParts(options.path, &translation, &rotation);
  std::optional<TauArtifact> tau;
  if (!options.tau.empty()) {
    tau = ReadTauArtifact(options.tau);
    if (IsVolumeValidity(path.validity) && tau->validity != path.validity) {
      LogWarn("%s was estimated for --validity %s, the path was planned under %s", options.tau.c_str(),
              tau->validity.c_str(), path.validity.c_str());
    }
  }
  std::vector<std::pair<std::string, double>> stage_seconds;
  if (!options.times.empty()) stage_seconds = ReadStageSeconds(options.times);

  // The independent exact check of the file as written (path.csv when
  // given, interpolated the plain way): the verdict trusts no model.
  std::optional<ExactCheckReport> exact;
  // Volume modes bounded every intersection by tau while planning: an
  // interference the exact check cannot measure is left to that model.
  const UnmeasuredInterference unmeasured =
      IsVolumeValidity(path.validity) ? UnmeasuredInterference::kFastener : UnmeasuredInterference::kRigid;
  const double tolerance = RigidToleranceInSceneUnits(options.rigid_tolerance_mm, scene.units, nullptr);
  if (path.success && !path.waypoints.empty()) {
    const std::vector<Pose> written = options.csv_name.empty() ? path.waypoints : ReadPathCsv(options.csv_name);
    exact = ExactCheckPath(scene, written, tolerance, unmeasured);
    if (!exact->valid) LogWarn("the path fails the exact check: %s", exact->reason.c_str());
  }
  const bool removable = path.success && !path.waypoints.empty() && exact && exact->valid;
  // Not removable: what holds D (straight pulls from the installed pose).
  std::optional<BlockingReport> blocking;
  if (!removable) {
    // The exact check classified D's solids the same way: reused.
    blocking = ProbeWhatBlocks(scene, tolerance, unmeasured, exact ? exact->parts : nullptr);
  }
  const std::optional<MaxVolume> max = FindMaxVolume(path);
  const bool volume_mode = IsVolumeValidity(path.validity);
  // tau and psi: the path's own (what it was planned with), else the tau file's.
  double tau_value = std::nan(""), psi_value = std::nan("");
  if (volume_mode) {
    tau_value = path.tau;
    psi_value = path.psi;
  } else if (tau) {
    tau_value = tau->estimate.tau;
    psi_value = tau->estimate.psi;
  }
  double total = 0;
  for (const auto& [stage, seconds] : stage_seconds) total += seconds;
  if (options.times.empty()) total = path.stats.time_s;

  JsonObject json;
  json.String("schema", kVerdictSchema).Int("version", kVerdictSchemaVersion);
  json.String("producer", "ausbau-verdict").String("producer_version", AUSBAU_VERSION);
  json.Add("scene", JsonObject()
                        .String("name", scene.name)
                        .String("file", scene.file.string())
                        .String("units", scene.units)
                        .Text());
  json.Bool("removable", removable).String("status", removable ? "removable" : "not-removable");
  json.String("validity", path.validity).Number("tau", tau_value).Number("psi", psi_value);
  if (tau) {
    const TauEstimate& e = tau->estimate;
    json.Add("tau_estimate", JsonObject()
                                 .String("file", options.tau)
                                 .String("validity", tau->validity)
                                 .Number("tau", e.tau)
                                 .Number("tau_lowest", e.tau_lowest)
                                 .Number("psi", e.psi)
                                 .Int("rounds", e.rounds)
                                 .Bool("solved", e.solved)
                                 .Number("seconds", e.seconds)
                                 .Text());
  } else {
    json.Null("tau_estimate");
  }
  JsonObject path_json;
  path_json.String("file", options.path);
  if (options.csv_name.empty()) {
    path_json.Null("csv");
  } else {
    path_json.String("csv", options.csv_name);
  }
  path_json.Int("waypoints", static_cast<long long>(path.waypoints.size())).Int("inter_index", path.inter_index);
  json.Add("path", path_json.Text());
  if (max) {
    json.Add("max_labeled_mliv", JsonObject()
                                     .String("measure", path.validity)
                                     .Number("value", max->value)
                                     .Int("waypoint", max->index)
                                     .Int("part", max->part)
                                     .Number("deformability", max->deformability)
                                     .Bool("in_sigma_1", max->in_sigma_1)
                                     .Text());
  } else {
    json.Null("max_labeled_mliv");
  }
  if (exact) {
    const PartModel& parts = *exact->parts;
    json.Add("exact_check",
             JsonObject()
                 .Bool("valid", exact->valid)
                 .String("reason", exact->reason)
                 .String("file", options.csv_name.empty() ? options.path : options.csv_name)
                 .Number("rigid_tolerance", tolerance)
                 .Int("poses_checked", exact->poses_checked)
                 .Number("max_rigid_penetration", exact->max_rigid_depth)
                 .String("rigid_part", parts.Describe(exact->rigid_shell, true))
                 .String("static_part", parts.Describe(exact->static_shell, false))
                 .Int("at_segment", exact->worst_segment)
                 .Number("max_fastener_penetration", exact->max_fastener_depth)
                 .Int("fastener_shells", parts.FastenerCount())
                 .Int("shells", static_cast<long long>(parts.robot_shells.size()))
                 .Text());
  } else {
    json.Null("exact_check");
  }
  if (blocking) {
    std::string probes = "[";
    for (const BlockingProbe& p : blocking->probes) {
      const auto& parts = *blocking->parts;
      probes += std::string(probes.size() > 1 ? ", " : "") +
                JsonObject()
                    .Add("direction", "[" + JsonNumber(p.direction.x()) + ", " + JsonNumber(p.direction.y()) + ", " +
                                          JsonNumber(p.direction.z()) + "]")
                    .Number("free_distance", p.free_distance)
                    .Bool("gets_out", p.separated)
                    .Number("depth", p.separated ? std::nan("") : p.depth)
                    .String("rigid_part", p.separated ? "" : parts.Describe(p.rigid_shell, true))
                    .String("static_part", p.separated ? "" : parts.Describe(p.static_shell, false))
                    .Text();
    }
    probes += "]";
    json.Add("what_blocks", JsonObject().String("summary", blocking->summary).Add("straight_pulls", probes).Text());
  } else {
    json.Null("what_blocks");
  }
  json.Add("length", JsonObject()
                         .Number("normalized", removable ? path.length_normalized : std::nan(""))
                         .Number("translation", removable ? translation : std::nan(""))
                         .Number("rotation", removable ? rotation : std::nan(""))
                         .Text());
  json.Add("planner", JsonObject()
                          .String("name", path.planner)
                          .Number("seconds", path.stats.time_s)
                          .Int("iterations", path.stats.iterations)
                          .Int("nodes", path.stats.nodes)
                          .Int("validity_checks", path.stats.collision_checks)
                          .Int("invalid_checks", path.stats.invalid_checks)
                          .Text());
  JsonObject seconds_json;
  for (const auto& [stage, seconds] : stage_seconds) seconds_json.Number(stage, seconds);
  json.Add("stage_seconds", seconds_json.Text());
  json.Number("total_seconds", total);
  if (options.budget >= 0) json.Number("budget_seconds", options.budget).Bool("within_budget", total <= options.budget);
  WriteTextFileAtomically(options.output, json.Text() + "\n");

  // The human summary (stdout; the log goes to stderr).
  std::printf("%s: %s\n", scene.name.c_str(), removable ? "REMOVABLE" : "NOT REMOVABLE");
  if (max) {
    std::printf("  max %s: %.6g %s^3 at waypoint %d of %zu", path.validity.c_str(), max->value, scene.units.c_str(),
                max->index, path.waypoints.size());
    if (max->part >= 0) std::printf(" (part %d, deformability %.2f)", max->part, max->deformability);
    std::printf(", %s sigma_1 (tau %.6g)\n", max->in_sigma_1 ? "in" : "outside", tau_value);
  }
  if (removable) {
    std::printf("  path: %s (%zu waypoints, length %.4f normalized)\n",
                options.csv_name.empty() ? options.path.c_str() : options.csv_name.c_str(), path.waypoints.size(),
                path.length_normalized);
  }
  if (exact) {
    std::printf("  exact check of %s: %s; deepest rigid penetration %.4g %s (tolerance %.4g), fasteners %.4g %s\n",
                options.csv_name.empty() ? options.path.c_str() : options.csv_name.c_str(),
                exact->valid ? "passed" : ("FAILED: " + exact->reason).c_str(), exact->max_rigid_depth,
                scene.units.c_str(), tolerance, exact->max_fastener_depth, scene.units.c_str());
  }
  if (blocking) std::printf("  what blocks: %s\n", blocking->summary.c_str());
  std::printf("  time: %.2f s%s", total, options.times.empty() ? " (planner only)" : "");
  if (options.budget >= 0) std::printf(" (budget %.6g s: %s)", options.budget, total <= options.budget ? "within" : "exceeded");
  std::printf("\n  verdict: %s\n", options.output.c_str());
  std::fflush(stdout);
  return removable ? kExitOk : kExitNoPath;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  VerdictOptions options;
  return RunStage(
      {"ausbau-verdict", "Says whether D is removable and summarizes an InIState run as verdict.json."}, argc, argv,
      [&](CLI::App& app) {
        app.add_option("--scene", options.scene, "scene.yaml")->required();
        app.add_option("--path", options.path, "the final path artifact (ausbau-path), e.g. path-smooth.h5")
            ->required();
        app.add_option("--tau", options.tau, "tau artifact (ausbau-tau-estimate)");
        app.add_option("--times", options.times, "folder of <stage>.seconds files (scripts/timed.sh)");
        app.add_option("--budget", options.budget, "seconds; adds within_budget (total <= budget)")
            ->check(CLI::NonNegativeNumber);
        app.add_option("--csv-name", options.csv_name,
                       "the path's CSV file: checked exactly as written (plain interpolation) and recorded");
        app.add_option("--rigid-tolerance", options.rigid_tolerance_mm,
                       "how deep D's rigid part may touch into S along the path, in mm (scene units converted)")
            ->capture_default_str();
        app.add_option("-o,--output", options.output, "verdict (JSON, schemas/verdict.md)")->capture_default_str();
      },
      [&] { return Run(options); });
}
