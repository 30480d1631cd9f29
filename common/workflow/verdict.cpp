#include "workflow/verdict.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "collision/scene_parts.h"
#include "core/error.h"
#include "core/format.h"
#include "core/json_writer.h"
#include "core/log.h"
#include "workflow/made_from.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

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
  static const char* const kOrder[] = {"scene-gen",    "voxelize", "medial-spheres", "pbd-label", "distfield-build",
                                       "tau-estimate", "plan",     "smooth",         "verdict",   "report"};
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

// A path the verdict can judge at all: finite numbers throughout (a NaN
// volume or length must not reach a "removable" line), and a claimed success
// with at least one waypoint (one: D already in its goal at the installed
// pose, clear of S; JudgeRun judges it as staying there). Where it starts
// and ends is the exact check's part (planning/exact_check.h: the start
// pose, the scene's goal at the end), which a removable verdict requires.
void CheckPathIsJudgeable(const std::string& file, const PathArtifact& path) {
  for (std::size_t i = 0; i < path.waypoints.size(); ++i) {
    const Pose& pose = path.waypoints[i];
    if (!pose.t.allFinite() || !pose.q.coeffs().allFinite()) {
      throw InputErrorAt(file, "waypoint " + std::to_string(i) + " is not finite");
    }
  }
  const auto check_values = [&](const std::vector<double>& values, const char* what) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (!std::isfinite(values[i])) {
        throw InputErrorAt(file, std::string(what) + " of waypoint " + std::to_string(i) + " is not finite");
      }
    }
  };
  check_values(path.waypoint_volume, "the volume");
  check_values(path.waypoint_deformability, "the deformability");
  const double lengths[] = {path.length_normalized, path.length_translation, path.length_rotation};
  for (const double length : lengths) {
    if (!std::isfinite(length) || length < 0) throw InputErrorAt(file, "a path length is not a finite number >= 0");
  }
  if (!std::isfinite(path.tau) || !std::isfinite(path.psi)) throw InputErrorAt(file, "tau or psi is not finite");
  if (path.success && path.waypoints.empty()) {
    throw InputErrorAt(file, "claims success with 0 waypoints; a removal needs at least the start pose");
  }
}

std::string PoseJson(const Pose& pose) {
  return JsonWriter().Add("t", JsonVector(pose.t)).Add("q", JsonQuaternion(pose.q)).Text();
}

// The path's quality figures and clearance (path_quality.h), with a warning
// where it comes closer to S than the clearance it was meant to keep.
// `classified`: D's parts as the exact check classified them (or null).
void JudgePathQuality(const Scene& scene, const PartModel* classified, Verdict* v) {
  if (!v->path.success || v->path.waypoints.size() < 2) return;
  v->quality = MeasurePathQuality(scene, v->path, v->inputs.rigid_tolerance_mm, classified);
  const std::string warning = ClearanceWarning(*v->quality, v->units);
  if (!warning.empty()) LogWarn("%s", warning.c_str());
}

}  // namespace

std::string PartContactJson(const PartContact& c) {
  JsonWriter json;
  json.String("part", c.name).Int("index", c.part).Bool("intersects", c.intersects);
  if (c.intersects) {
    json.Number("depth", c.depth).Bool("depth_exact", c.depth_exact).Null("distance");
  } else {
    json.Null("depth").Bool("depth_exact", false).Number("distance", c.distance);
  }
  return json.Add("point", JsonVector(c.point)).Bool("frees", c.frees).Text();
}

Scene WithoutStaticPart(const Scene& scene, int part) {
  const auto part_of = [&](std::size_t t) {
    return t < scene.static_part_of_triangle.size() ? scene.static_part_of_triangle[t] : 0;
  };
  Scene reduced = scene;
  reduced.static_mesh = scene.static_mesh.KeepTriangles([&](std::size_t t) { return part_of(t) != part; });
  reduced.static_part_of_triangle.clear();
  for (std::size_t t = 0; t < scene.static_mesh.triangles.size(); ++t)
    if (part_of(t) != part) reduced.static_part_of_triangle.push_back(part_of(t));
  return reduced;
}

namespace {

// Whether D comes out of S along a straight pull from the installed pose
// (ProbeWhatBlocks) once part `part` of S is taken away; none where S is
// nothing else.
std::optional<bool> PullFreesWithout(const Scene& scene, int part, double tolerance,
                                     UnmeasuredInterference unmeasured) {
  const Scene reduced = WithoutStaticPart(scene, part);
  if (reduced.static_mesh.triangles.empty()) return std::nullopt;
  const BlockingReport probe = ProbeWhatBlocks(reduced, tolerance, unmeasured, nullptr, true);
  return probe.parts->rigid_interference.empty() &&
         std::any_of(probe.probes.begin(), probe.probes.end(), [](const BlockingProbe& p) { return p.separated; });
}

}  // namespace

bool BlockedAtPartialEnd(const PathArtifact& path) {
  return !path.success && !path.partial_waypoints.empty() && !path.stopped_by_budget;
}

Pose WhereBlocked(const PathArtifact& path, const Scene& scene) {
  return BlockedAtPartialEnd(path) ? path.partial_waypoints.back() : scene.start;
}

std::optional<PullStopper> FindPullStopper(const Scene& scene, const BlockingReport& pulls,
                                           const std::vector<PartContact>& contacts, double tolerance,
                                           UnmeasuredInterference unmeasured) {
  // The blocked pulls, farthest first (ties: the probes' order, as
  // `farthest` picks): the part that stops a pull far from D's contacts (a
  // cap over a post that slid up to it) is tried before one that stops a
  // pull at once.
  std::vector<int> blocked;
  for (int i = 0; i < static_cast<int>(pulls.probes.size()); ++i) {
    const BlockingProbe& p = pulls.probes[i];
    if (!p.separated && !p.unfinished && !p.static_part_name.empty()) blocked.push_back(i);
  }
  std::stable_sort(blocked.begin(), blocked.end(),
                   [&](int a, int b) { return pulls.probes[a].free_distance > pulls.probes[b].free_distance; });
  if (pulls.farthest >= 0) {  // the report's farthest first, whatever the sort made of ties
    const auto at = std::find(blocked.begin(), blocked.end(), pulls.farthest);
    if (at != blocked.end()) std::rotate(blocked.begin(), at, at + 1);
  }
  std::optional<PullStopper> first;
  std::set<std::string> tried;
  for (const int i : blocked) {
    const std::string& name = pulls.probes[i].static_part_name;
    if (!tried.insert(name).second) continue;
    if (std::any_of(contacts.begin(), contacts.end(), [&](const PartContact& c) { return c.name == name; }))
      continue;  // among the contacts, taken away there already
    const auto named = std::find(scene.static_part_names.begin(), scene.static_part_names.end(), name);
    if (named == scene.static_part_names.end()) continue;
    const int part = static_cast<int>(named - scene.static_part_names.begin());
    const std::optional<bool> frees = PullFreesWithout(scene, part, tolerance, unmeasured);
    if (!frees) continue;
    LogInfo("what blocks: without %s, which stops a straight pull after %.4g, %s", name.c_str(),
            pulls.probes[i].free_distance, *frees ? "D comes out along a straight pull" : "D is still held");
    if (*frees) return PullStopper{part, name, true};
    if (!first) first = PullStopper{part, name, false};
  }
  return first;
}

std::vector<PartContact> FindBlockingParts(const Scene& scene, const Pose& pose, double tolerance,
                                           UnmeasuredInterference unmeasured) {
  TriangleMesh robot = scene.dynamic_mesh;
  for (auto& vertex : robot.vertices) vertex -= scene.dynamic_origin;
  const double reach = 0.05 * robot.Bounds().Size().norm();
  std::vector<PartContact> contacts = MeasurePartContacts(robot, pose, scene.static_mesh, scene.static_part_of_triangle,
                                                          scene.static_part_names, reach, 8);
  // Which of them, taken away alone, lets D out along a straight pull: the
  // parts that stop its motion come first (a post is held by the cap on
  // it, not by the base it stands in, however deep either contact is).
  // Work, not seconds (at most 8 parts, ProbeWhatBlocks' pulls for each
  // until one gets D out): the same answer under any load, but no time
  // limit either (a pull sliding in contact along curved or coincident
  // faces can take minutes). Not where S is one part.
  const std::set<int> parts(scene.static_part_of_triangle.begin(), scene.static_part_of_triangle.end());
  if (parts.size() < 2 || !(tolerance > 0)) return contacts;
  for (PartContact& contact : contacts) {
    const std::optional<bool> frees = PullFreesWithout(scene, contact.part, tolerance, unmeasured);
    if (!frees) continue;
    contact.frees = *frees;
    LogInfo("what blocks: without %s, %s", contact.name.c_str(),
            contact.frees ? "D comes out along a straight pull" : "D is still held");
  }
  std::stable_partition(contacts.begin(), contacts.end(), [](const PartContact& c) { return c.frees; });
  return contacts;
}

namespace {

// Verdict::pull_stopper (FindPullStopper), where D's blocked straight pulls
// are stopped by parts its contacts do not include.
void AddPullStopper(const Scene& scene, UnmeasuredInterference unmeasured, Verdict* v) {
  if (!v->blocking) return;
  const std::optional<PullStopper> stopper =
      FindPullStopper(scene, *v->blocking, v->blockers, v->tolerance, unmeasured);
  if (!stopper) return;
  v->pull_stopper = stopper->name;
  v->pull_stopper_frees = stopper->frees;
}

}  // namespace

std::string VerdictStatusDetail(const Verdict& v) {
  if (v.removable) return "removable";
  if (v.stopped_by_budget) return "not-removable (budget)";
  if (!v.path.success) return "not-removable (no path)";
  return "not-removable (exact check failed)";
}

Verdict JudgeRun(const Scene& scene, const VerdictInputs& options) {
  Verdict v;
  v.inputs = options;
  v.scene_name = scene.name;
  v.scene_file = scene.file.string();
  v.units = scene.units;
  v.path = ReadPathArtifact(options.path);
  const PathArtifact& path = v.path;
  CheckPathIsJudgeable(options.path, path);
  CheckMadeFrom(options.path, kPathSchema, kPathSchemaVersion, scene, MadeFrom::kMeshes);
  if (!path.scene.empty() && path.scene != scene.name) {
    throw InputErrorAt(options.path, "was planned for scene '" + path.scene + "', not '" + scene.name + "'");
  }
  std::optional<TauArtifact>& tau = v.tau;
  if (!options.tau.empty()) {
    tau = ReadTauArtifact(options.tau);
    CheckMadeFrom(options.tau, kTauSchema, kTauSchemaVersion, scene, MadeFrom::kMeshes);
    if (IsVolumeValidity(path.validity) && tau->validity != path.validity) {
      LogWarn("%s was estimated for --validity %s, the path was planned under %s", options.tau.c_str(),
              ValidityModeName(tau->validity).c_str(), ValidityModeName(path.validity).c_str());
    }
  }
  if (!options.times.empty()) v.stage_seconds = ReadStageSeconds(options.times);

  // The independent exact check of the file as written (path.csv when
  // given, interpolated the plain way): the verdict trusts no model.
  std::optional<ExactCheckReport>& exact = v.exact;
  // Volume modes bounded every intersection by tau while planning: an
  // interference the exact check cannot measure is left to that model.
  const UnmeasuredInterference unmeasured =
      IsVolumeValidity(path.validity) ? UnmeasuredInterference::kFastener : UnmeasuredInterference::kRigid;
  v.tolerance = RigidToleranceInSceneUnits(options.rigid_tolerance_mm, scene, nullptr);
  if (path.success && !path.waypoints.empty()) {
    std::vector<Pose> written = options.csv.empty() ? path.waypoints : ReadPathCsv(options.csv);
    // One waypoint: the planner found D already in its goal (by default
    // clear of S) at the installed pose. Judged as the motion that stays
    // there: removable, trivially, when that pose is the start and passes.
    v.already_in_goal = written.size() == 1;
    if (v.already_in_goal) written.push_back(written.front());
    exact = ExactCheckPath(scene, written, v.tolerance, unmeasured, options.progress);
    if (!exact->valid) LogWarn("the path fails the exact check: %s", exact->reason.c_str());
  }
  // Removable only when the path as written passes the exact check, starts
  // at the installed pose and ends in the scene's goal (RemovesPart, the
  // order's definition too).
  v.removable = path.success && !path.waypoints.empty() && exact && RemovesPart(*exact);
  // Not removable: what holds D (straight pulls from the installed pose).
  if (!v.removable) {
    // The exact check classified D's solids the same way: reused.
    v.blocking = ProbeWhatBlocks(scene, v.tolerance, unmeasured, exact ? exact->parts : nullptr);
    v.stopped_by_budget = !path.success && path.stopped_by_budget;
    // The partial path itself is still written, labelled cut short.
    v.blocked_at_partial_end = BlockedAtPartialEnd(path);
    v.blocked_at = WhereBlocked(path, scene);
    v.blockers = FindBlockingParts(scene, v.blocked_at, v.tolerance, unmeasured);
    AddPullStopper(scene, unmeasured, &v);
  }
  v.max_volume = FindMaxVolume(path);
  // The exact check's classification of D, where it ran (rigid: at the
  // rigid rule).
  JudgePathQuality(scene, exact && unmeasured == UnmeasuredInterference::kRigid ? exact->parts.get() : nullptr, &v);
  const bool volume_mode = IsVolumeValidity(path.validity);
  // tau and psi: the path's own (what it was planned with), else the tau file's.
  v.tau_value = std::nan("");
  v.psi_value = std::nan("");
  if (volume_mode) {
    v.tau_value = path.tau;
    v.psi_value = path.psi;
  } else if (tau) {
    v.tau_value = tau->estimate.tau;
    v.psi_value = tau->estimate.psi;
  }
  v.total_seconds = 0;
  for (const auto& [stage, seconds] : v.stage_seconds) v.total_seconds += seconds;
  if (options.times.empty()) v.total_seconds = path.stats.time_s;
  return v;
}

namespace {

// The sections of verdict.json (VerdictJson), each added to `json`.

// Not removable: why, and what blocks D where it got to (absent for a
// removable part, whose files stay as they were).
void AddWhyNotRemovable(const Verdict& v, JsonWriter& json) {
  if (v.removable) return;
  json.String("status_detail", VerdictStatusDetail(v)).Bool("stopped_by_budget", v.stopped_by_budget);
  std::string partial = "[";
  for (const Pose& pose : v.path.partial_waypoints) partial += (partial.size() > 1 ? ", " : "") + PoseJson(pose);
  json.Add("partial_path", JsonWriter()
                               .Int("waypoints", static_cast<long long>(v.path.partial_waypoints.size()))
                               .Add("poses", partial + "]")
                               .Text());
  std::string blockers = "[";
  for (const PartContact& c : v.blockers) blockers += (blockers.size() > 1 ? ", " : "") + PartContactJson(c);
  json.Add("blocked_by", JsonWriter()
                             .String("at", v.blocked_at_partial_end ? "end of the partial path" : "installed pose")
                             .Add("pose", PoseJson(v.blocked_at))
                             .Add("parts", blockers + "]")
                             .Text());
}

void AddTauEstimate(const Verdict& v, JsonWriter& json) {
  const auto& tau = v.tau;
  const VerdictInputs& options = v.inputs;
  if (tau) {
    const TauEstimate& e = tau->estimate;
    json.Add("tau_estimate", JsonWriter()
                                 .String("file", options.tau)
                                 .String("validity", ValidityModeName(tau->validity))
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
}

void AddExactCheck(const Verdict& v, JsonWriter& json) {
  const VerdictInputs& options = v.inputs;
  const auto& exact = v.exact;
  if (exact) {
    const PartModel& parts = *exact->parts;
    // Installed fit interferences (collision/rigid_depth.h FitRule): drawn
    // out along, never pushed deeper than installed plus the tolerance.
    std::string fits = "[";
    for (const FitInterference& fit : parts.fits) {
      fits +=
          std::string(fits.size() > 1 ? ", " : "") + JsonWriter()
                                                         .String("rigid_part", parts.Describe(fit.robot_shell, true))
                                                         .String("static_part", parts.Describe(fit.static_shell, false))
                                                         .Number("installed_depth", fit.installed_depth)
                                                         .Number("overlap_area", fit.area)
                                                         .Text();
    }
    fits += "]";
    json.Add("exact_check", JsonWriter()
                                .Bool("valid", exact->valid)
                                .String("reason", exact->reason)
                                .String("file", options.csv.empty() ? options.path : options.csv)
                                .Number("rigid_tolerance", v.tolerance)
                                .Int("poses_checked", exact->poses_checked)
                                .Int("stretches_proved", exact->stretches_proved)
                                .Number("max_rigid_penetration", exact->max_rigid_depth)
                                .String("rigid_part", parts.Describe(exact->rigid_shell, true))
                                .String("static_part", parts.Describe(exact->static_shell, false))
                                .Int("at_segment", exact->worst_segment)
                                .Number("max_fastener_penetration", exact->max_fastener_depth)
                                .Int("fastener_shells", parts.FastenerCount())
                                .Add("fit_interferences", fits)
                                .Int("shells", static_cast<long long>(parts.robot_shells.size()))
                                .Text());
  } else {
    json.Null("exact_check");
  }
}

void AddWhatBlocks(const Verdict& v, JsonWriter& json) {
  const auto& blocking = v.blocking;
  if (blocking) {
    std::string probes = "[";
    for (const BlockingProbe& p : blocking->probes) {
      const auto& parts = *blocking->parts;
      const bool blocked = !p.separated && !p.unfinished && p.rigid_shell >= 0;
      probes += std::string(probes.size() > 1 ? ", " : "") +
                JsonWriter()
                    .Add("direction", "[" + JsonNumber(p.direction.x()) + ", " + JsonNumber(p.direction.y()) + ", " +
                                          JsonNumber(p.direction.z()) + "]")
                    .Number("free_distance", p.free_distance)
                    .Bool("gets_out", p.separated)
                    .Bool("unfinished", p.unfinished)
                    .Number("depth", blocked ? p.depth : std::nan(""))
                    .String("rigid_part", blocked ? parts.Describe(p.rigid_shell, true) : "")
                    .String("static_part", blocked ? parts.Describe(p.static_shell, false) : "")
                    .String("static_part_name", blocked ? p.static_part_name : "")
                    .Text();
    }
    probes += "]";
    JsonWriter what;
    what.String("summary", blocking->summary).Add("straight_pulls", probes);
    if (v.pull_stopper.empty()) {
      what.Null("pull_stopper");
    } else {
      what.Add("pull_stopper", JsonWriter().String("part", v.pull_stopper).Bool("frees", v.pull_stopper_frees).Text());
    }
    json.Add("what_blocks", what.Text());
  } else {
    json.Null("what_blocks");
  }
}

}  // namespace

std::string VerdictJson(const Verdict& v) {
  const VerdictInputs& options = v.inputs;
  const PathArtifact& path = v.path;
  const auto& max = v.max_volume;
  const bool removable = v.removable;
  JsonWriter json;
  json.String("schema", kVerdictSchema).Int("version", kVerdictSchemaVersion);
  json.String("producer", "ausbau-verdict").String("producer_version", AUSBAU_VERSION);
  json.Add("scene",
           JsonWriter().String("name", v.scene_name).String("file", v.scene_file).String("units", v.units).Text());
  json.Bool("removable", removable).String("status", removable ? "removable" : "not-removable");
  // Only where it holds (the recorded verdicts of other runs stay the same).
  if (removable && v.already_in_goal) json.Bool("already_in_goal", true);
  // Where a clock (a time limit, a safety net, or the budget) cut a stage
  // short, the result is not the deterministic one; said only then, so that
  // verdicts of runs that did all their counted work stay as they were. A
  // removable path whose smoothing was cut short is still exactly checked:
  // removable, less smooth than it would be.
  if (v.path.smoothing_cut_short) json.Bool("smoothing_cut_short", true);
  if (v.tau && v.tau->estimate.cut_short) json.Bool("tau_estimate_cut_short", true);
  AddWhyNotRemovable(v, json);
  json.String("validity", ValidityModeName(path.validity)).Number("tau", v.tau_value).Number("psi", v.psi_value);
  AddTauEstimate(v, json);
  JsonWriter path_json;
  path_json.String("file", options.path);
  if (options.csv.empty()) {
    path_json.Null("csv");
  } else {
    path_json.String("csv", options.csv);
  }
  path_json.Int("waypoints", static_cast<long long>(path.waypoints.size())).Int("inter_index", path.inter_index);
  json.Add("path", path_json.Text());
  if (max) {
    json.Add("max_labeled_mliv", JsonWriter()
                                     .String("measure", ValidityModeName(path.validity))
                                     .Number("value", max->value)
                                     .Int("waypoint", max->index)
                                     .Int("part", max->part)
                                     .Number("deformability", max->deformability)
                                     .Bool("in_sigma_1", max->in_sigma_1)
                                     .Text());
  } else {
    json.Null("max_labeled_mliv");
  }
  AddExactCheck(v, json);
  AddWhatBlocks(v, json);
  json.Add("length", JsonWriter()
                         .Number("normalized", removable ? path.length_normalized : std::nan(""))
                         .Number("translation", removable ? path.length_translation : std::nan(""))
                         .Number("rotation", removable ? path.length_rotation : std::nan(""))
                         .Text());
  json.Add("path_quality", v.quality ? PathQualityJson(*v.quality) : "null");
  json.Add("planner", JsonWriter()
                          .String("name", path.planner)
                          .Number("seconds", path.stats.time_s)
                          .Int("iterations", path.stats.iterations)
                          .Int("nodes", path.stats.nodes)
                          .Int("validity_checks", path.stats.collision_checks)
                          .Int("invalid_checks", path.stats.invalid_checks)
                          .Text());
  JsonWriter seconds_json;
  for (const auto& [stage, seconds] : v.stage_seconds) seconds_json.Number(stage, seconds);
  json.Add("stage_seconds", seconds_json.Text());
  json.Number("total_seconds", v.total_seconds);
  if (options.budget >= 0)
    json.Number("budget_seconds", options.budget).Bool("within_budget", v.total_seconds <= options.budget);
  return json.Text() + "\n";
}

void PrintVerdictSummary(const Verdict& v, const std::string& verdict_file, std::FILE* terminal) {
  // Written into memory first and shown with TerminalSafeLines: the scene's
  // name (its file's stem, when it gives none) and its parts' names come
  // from files, and their control characters must not reach the terminal.
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  if (out == nullptr) throw std::runtime_error("cannot format the verdict's summary");
  const VerdictInputs& options = v.inputs;
  const PathArtifact& path = v.path;
  const auto& exact = v.exact;
  const auto& max = v.max_volume;
  const char* units = v.units.c_str();
  std::fprintf(out, "%s: %s%s\n", v.scene_name.c_str(), v.removable ? "REMOVABLE" : "NOT REMOVABLE",
               v.stopped_by_budget ? " (budget: a time limit or the time budget ended the search)" : "");
  if (v.path.smoothing_cut_short || (v.tau && v.tau->estimate.cut_short)) {
    std::fprintf(out, "  cut short by the clock (a safety net): %s%s%s; a re-run on an idle machine may differ\n",
                 v.tau && v.tau->estimate.cut_short ? "the tau estimate" : "",
                 v.path.smoothing_cut_short && v.tau && v.tau->estimate.cut_short ? ", " : "",
                 v.path.smoothing_cut_short ? "smoothing" : "");
  }
  if (max) {
    std::fprintf(out, "  max %s: %.6g %s^3 at waypoint %d of %zu", ValidityModeName(path.validity).c_str(), max->value,
                 units, max->index, path.waypoints.size());
    if (max->part >= 0) std::fprintf(out, " (part %d, deformability %.2f)", max->part, max->deformability);
    std::fprintf(out, ", %s sigma_1 (tau %.6g)\n", max->in_sigma_1 ? "in" : "outside", v.tau_value);
  }
  if (v.removable && v.already_in_goal) {
    std::fprintf(out, "  already separated: D is clear of S (in its goal) at the installed pose; nothing to move\n");
  }
  if (v.removable) {
    std::fprintf(out, "  path: %s (%zu waypoints, length %.4f normalized)\n",
                 options.csv.empty() ? options.path.c_str() : options.csv.c_str(), path.waypoints.size(),
                 path.length_normalized);
  }
  if (exact) {
    std::fprintf(out,
                 "  exact check of %s: %s; deepest rigid penetration %.4g %s (tolerance %.4g), fasteners %.4g %s\n",
                 options.csv.empty() ? options.path.c_str() : options.csv.c_str(),
                 exact->valid ? "passed" : ("FAILED: " + exact->reason).c_str(), exact->max_rigid_depth, units,
                 v.tolerance, exact->max_fastener_depth, units);
    for (const FitInterference& fit : exact->parts->fits) {
      std::fprintf(out,
                   "  fit interference at the installed pose: %s in %s, %.4g %s deep (allowed: never deeper than "
                   "that plus the tolerance)\n",
                   exact->parts->Describe(fit.robot_shell, true).c_str(),
                   exact->parts->Describe(fit.static_shell, false).c_str(), fit.installed_depth, units);
    }
  }
  if (v.quality) std::fprintf(out, "  quality: %s\n", PathQualityLine(*v.quality, v.units).c_str());
  if (v.blocking) std::fprintf(out, "  what blocks: %s\n", v.blocking->summary.c_str());
  for (const PartContact& c : v.blockers) {
    std::fprintf(out, "  blocked by (at the %s): %s\n",
                 v.blocked_at_partial_end ? "end of the best partial path" : "installed pose",
                 DescribePartContact(c).c_str());
  }
  if (!v.pull_stopper.empty()) {
    std::fprintf(out, "  a straight pull is stopped by %s; without it, %s\n", v.pull_stopper.c_str(),
                 v.pull_stopper_frees ? "D comes out along a straight pull" : "D is still held");
  }
  std::fprintf(out, "  time: %.2f s%s", v.total_seconds, options.times.empty() ? " (planner only)" : "");
  if (options.budget >= 0)
    std::fprintf(out, " (budget %.6g s: %s)", options.budget,
                 v.total_seconds <= options.budget ? "within" : "exceeded");
  std::fprintf(out, "\n  verdict: %s\n", verdict_file.c_str());
  std::fclose(out);
  const std::string text(buffer, size);
  std::free(buffer);
  std::fputs(TerminalSafeLines(text).c_str(), terminal);
  std::fflush(terminal);
}

}  // namespace ausbau
