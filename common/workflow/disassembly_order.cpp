#include "workflow/disassembly_order.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "artifact/run_files.h"
#include "collision/part_contacts.h"
#include "collision/scene_parts.h"
#include "core/error.h"
#include "core/json_writer.h"
#include "core/log.h"
#include "planning/exact_check.h"
#include "scene/scene.h"
#include "workflow/verdict.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// The folder of a part's attempts (and the name of its attempt scenes):
// its name with each control character (C0, DEL, C1: a newline or an escape
// sequence from a file name) as '_', so that a folder listing or a scene
// name cannot carry one; letters of any script stay as they are. CheckParts
// has refused '/', '\\', "." and ".."; the name itself stays as given (order.json
// escapes it, the terminal shows it escaped).
std::string PartFolderName(const std::string& name) {
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (c < 0x20 || c == 0x7f) {
      out += '_';
    } else if (c == 0xc2 && i + 1 < name.size() && static_cast<unsigned char>(name[i + 1]) >= 0x80 &&
               static_cast<unsigned char>(name[i + 1]) <= 0x9f) {
      out += '_';
      ++i;
    } else {
      out += name[i];
    }
  }
  return out;
}

double Now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

// The scene of one attempt: `part` as D, `others` as S (one static file
// each, named by part), written to folder/scene.yaml and read back the way
// every stage reads a scene.
Scene AttemptScene(const AssemblyPart& part, const std::vector<const AssemblyPart*>& others, int round,
                   const DisassemblyOrderOptions& options, const fs::path& folder) {
  Scene description;
  description.name = PartFolderName(part.name) + "-round-" + std::to_string(round);
  description.units = options.units;
  description.dynamic_file = fs::absolute(part.file);
  for (const AssemblyPart* other : others) description.static_files.push_back(fs::absolute(other->file));
  SaveSceneYaml(description, folder / "scene.yaml");
  Scene scene = LoadScene(folder / "scene.yaml");
  scene.static_part_names.clear();
  for (const AssemblyPart* other : others) scene.static_part_names.push_back(other->name);
  return scene;
}

// The part that stops one of D's straight pulls, is none of the parts D
// touches at `at` and frees D when taken away (FindPullStopper: a cover
// over a post that touches only its base), with its distance there, after
// the contacts that free D and before the rest: the order points the part
// at what holds it where it stands, not where a search got in its seconds.
void AddFreeingPullStopper(const Scene& scene, const Pose& at, double tolerance, std::vector<PartContact>* blocked_by) {
  if (std::set<int>(scene.static_part_of_triangle.begin(), scene.static_part_of_triangle.end()).size() < 2) return;
  const std::optional<PullStopper> stopper =
      FindPullStopper(scene, ProbeWhatBlocks(scene, tolerance), *blocked_by, tolerance);
  if (!stopper || !stopper->frees) return;
  TriangleMesh robot = scene.dynamic_mesh;
  for (auto& vertex : robot.vertices) vertex -= scene.dynamic_origin;
  const int parts = static_cast<int>(scene.static_part_names.size());
  for (PartContact contact :
       MeasurePartContacts(robot, at, scene.static_mesh, scene.static_part_of_triangle, scene.static_part_names,
                           std::numeric_limits<double>::infinity(), parts)) {
    if (contact.part != stopper->part) continue;
    contact.frees = true;
    const auto first_held =
        std::find_if(blocked_by->begin(), blocked_by->end(), [](const PartContact& c) { return !c.frees; });
    blocked_by->insert(first_held, contact);
    return;
  }
}

// One attempt: plan under rigid-exact within the part's budget, then the
// verdict's judgement of the result (the exact check of the path as
// written; where it is not removable, the parts that block D where it got
// to, WhereBlocked, and the part that stops a straight pull and frees it).
PartAttempt TryPart(const AssemblyPart& part, const std::vector<const AssemblyPart*>& others, int round,
                    const DisassemblyOrderOptions& options) {
  const double begin = Now();
  PartAttempt attempt;
  attempt.round = round;
  attempt.part = part.name;
  const fs::path folder = options.out / ("round-" + std::to_string(round)) / PartFolderName(part.name);
  fs::create_directories(folder);
  attempt.folder = folder.string();
  const Scene scene = AttemptScene(part, others, round, options, folder);
  PlanSceneOptions plan = options.plan;
  plan.validity = ValidityMode::kRigidExact;
  // The verdict's share after planning, as pipelines/inistate.mk leaves it.
  plan.deadline = begin + 0.75 * options.part_budget_s;
  const PlannedPath planned = PlanScene(scene, plan);
  const PathArtifact& path = planned.artifact;
  Provenance provenance;
  provenance.producer = "ausbau-order";
  provenance.producer_version = AUSBAU_VERSION;
  WritePathArtifact(folder / kRunFilePath, path, provenance);
  const std::vector<Pose>& written = path.success ? path.waypoints : path.partial_waypoints;
  WritePathCsv(folder / kRunFilePathCsv, written);
  attempt.waypoints = written.size();

  const double tolerance = RigidToleranceInSceneUnits(plan.volume.rigid_tolerance_mm, scene, nullptr);
  if (path.success && !path.waypoints.empty()) {
    // One waypoint: the part is already clear of the rest where it is;
    // judged as staying there, as ausbau-verdict does.
    std::vector<Pose> judged = path.waypoints;
    if (judged.size() == 1) judged.push_back(judged.front());
    const ExactCheckReport exact = ExactCheckPath(scene, judged, tolerance);
    // The verdict's definition (RemovesPart): this scene has no goal, so
    // "in the goal" is D's AABB separated from S's.
    attempt.removable = RemovesPart(exact);
  }
  if (attempt.removable) {
    attempt.status_detail = "removable";
  } else {
    attempt.status_detail = path.success             ? "not-removable (exact check failed)"
                            : path.stopped_by_budget ? "not-removable (budget)"
                                                     : "not-removable (no path)";
    const Pose at = WhereBlocked(path, scene);
    attempt.blocked_by = FindBlockingParts(scene, at, tolerance);
    AddFreeingPullStopper(scene, at, tolerance, &attempt.blocked_by);
  }
  attempt.seconds = Now() - begin;
  LogInfo("round %d: %s %s (%.1f s)%s%s", round, part.name.c_str(), attempt.status_detail.c_str(), attempt.seconds,
          attempt.blocked_by.empty() ? "" : ", blocked by ",
          attempt.blocked_by.empty() ? "" : DescribePartContact(attempt.blocked_by.front()).c_str());
  return attempt;
}

void CheckParts(const std::vector<AssemblyPart>& parts) {
  if (parts.size() < 2) throw InputError("--part: an assembly needs at least two parts");
  std::set<std::string> names, folders;
  bool any_movable = false;
  for (const AssemblyPart& part : parts) {
    if (part.name.empty() || part.name.find_first_of("/\\") != std::string::npos || part.name == "." ||
        part.name == "..") {
      throw InputErrorAt(part.file.string(), "part name '" + part.name + "' is empty or not a plain file name");
    }
    if (!names.insert(part.name).second) throw InputError("--part: the name '" + part.name + "' is given twice");
    if (!folders.insert(PartFolderName(part.name)).second) {
      throw InputError("--part: two names share the folder '" + PartFolderName(part.name) +
                       "' (their control characters are written as '_'); rename one");
    }
    std::error_code error;
    if (!fs::is_regular_file(part.file, error)) throw InputErrorAt(part.file.string(), "part file not found");
    // Each attempt's scene.yaml names the files, and a scene refuses file
    // names with control characters (scene/scene.h): said here, before any
    // round, rather than by the first attempt.
    if (PartFolderName(fs::absolute(part.file).string()) != fs::absolute(part.file).string()) {
      throw InputErrorAt(part.file.string(),
                         "the file's name holds control characters (a newline, an escape "
                         "sequence); rename the file");
    }
    any_movable = any_movable || !part.fixed;
  }
  if (!any_movable) throw InputError("--fixed: every part is fixed; nothing to take out");
}

}  // namespace

void DisassemblyOrderOptions::Check() const {
  if (!(part_budget_s > 0) || !std::isfinite(part_budget_s)) {
    throw InputError("--part-budget: must be a positive number of seconds");
  }
  if (out.empty()) throw InputError("--output-dir: required");
  std::error_code error;
  if (fs::exists(out, error) && !fs::is_directory(out, error)) {
    throw InputErrorAt(out.string(), "--output-dir: exists and is not a folder");
  }
  PlanSceneOptions rigid = plan;
  rigid.validity = ValidityMode::kRigidExact;
  rigid.Check();
}

std::vector<std::string> FindBlockingCycle(const std::vector<std::string>& remaining,
                                           const std::vector<PartAttempt>& round_attempts) {
  std::map<std::string, std::string> next;  // part -> its first blocker still in
  const std::set<std::string> in(remaining.begin(), remaining.end());
  for (const PartAttempt& attempt : round_attempts) {
    for (const PartContact& contact : attempt.blocked_by) {
      if (in.count(contact.name) != 0) {
        next[attempt.part] = contact.name;
        break;
      }
    }
  }
  if (remaining.empty()) return {};
  std::vector<std::string> walk{remaining.front()};
  while (true) {
    const auto it = next.find(walk.back());
    if (it == next.end()) return {};
    const auto seen = std::find(walk.begin(), walk.end(), it->second);
    if (seen != walk.end()) {
      std::vector<std::string> cycle(seen, walk.end());
      cycle.push_back(it->second);
      return cycle;
    }
    walk.push_back(it->second);
  }
}

std::vector<AssemblyPart> CollectAssemblyParts(const std::vector<std::string>& given, const std::string& dir,
                                               const std::vector<std::string>& fixed) {
  std::vector<AssemblyPart> parts;
  if (!dir.empty()) {
    std::error_code error;
    if (!fs::is_directory(dir, error)) throw InputErrorAt(dir, "--parts-dir: not a folder");
    std::vector<fs::path> files;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
      const std::string ext = entry.path().extension().string();
      if (entry.is_regular_file() && (ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".off" ||
                                      ext == ".dae" || ext == ".gltf" || ext == ".glb")) {
        files.push_back(entry.path());
      }
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) parts.push_back({file.stem().string(), file, false});
  }
  for (const std::string& text : given) {
    const auto equals = text.find('=');
    if (equals == std::string::npos) {
      parts.push_back({fs::path(text).stem().string(), text, false});
    } else {
      parts.push_back({text.substr(0, equals), text.substr(equals + 1), false});
    }
  }
  for (const std::string& name : fixed) {
    const auto it = std::find_if(parts.begin(), parts.end(), [&](const AssemblyPart& p) { return p.name == name; });
    if (it == parts.end()) throw InputError("--fixed: no part is named '" + name + "'");
    it->fixed = true;
  }
  return parts;
}

DisassemblyOrder PlanDisassemblyOrder(const std::vector<AssemblyPart>& parts, const DisassemblyOrderOptions& options) {
  options.Check();
  CheckParts(parts);
  DisassemblyOrder order;
  std::vector<const AssemblyPart*> in;
  for (const AssemblyPart& part : parts) {
    if (part.fixed) order.fixed.push_back(part.name);
    in.push_back(&part);
  }
  for (int round = 1;; ++round) {
    std::vector<const AssemblyPart*> movable;
    for (const AssemblyPart* part : in) {
      if (!part->fixed) movable.push_back(part);
    }
    if (movable.empty()) {
      order.complete = true;
      break;
    }
    // The last part with nothing left around it is out by itself.
    if (in.size() == 1) {
      order.steps.push_back({in.front()->name});
      order.sequence.push_back(in.front()->name);
      LogInfo("round %d: %s is the last part: nothing left around it", round, in.front()->name.c_str());
      order.complete = true;
      break;
    }
    std::vector<PartAttempt> attempts;
    std::vector<std::string> freed;
    for (const AssemblyPart* part : movable) {
      std::vector<const AssemblyPart*> others;
      for (const AssemblyPart* other : in) {
        if (other != part) others.push_back(other);
      }
      if (options.progress) options.progress(static_cast<std::int64_t>(attempts.size()), movable.size());
      attempts.push_back(TryPart(*part, others, round, options));
      if (attempts.back().removable) freed.push_back(part->name);
    }
    if (options.progress) options.progress(movable.size(), movable.size());
    order.attempts.insert(order.attempts.end(), attempts.begin(), attempts.end());
    if (freed.empty()) {
      for (const AssemblyPart* part : movable) order.remaining.push_back(part->name);
      order.cycle = FindBlockingCycle(order.remaining, attempts);
      break;
    }
    order.steps.push_back(freed);
    order.sequence.insert(order.sequence.end(), freed.begin(), freed.end());
    in.erase(std::remove_if(in.begin(), in.end(),
                            [&](const AssemblyPart* part) {
                              return std::find(freed.begin(), freed.end(), part->name) != freed.end();
                            }),
             in.end());
  }
  return order;
}

std::string DisassemblyOrderJson(const DisassemblyOrder& order, const DisassemblyOrderOptions& options) {
  const auto names = [](const std::vector<std::string>& list) {
    std::string text = "[";
    for (const std::string& name : list) text += (text.size() > 1 ? ", " : "") + JsonString(name);
    return text + "]";
  };
  std::string steps = "[";
  for (const auto& step : order.steps) steps += (steps.size() > 1 ? ", " : "") + names(step);
  std::string attempts = "[";
  for (const PartAttempt& a : order.attempts) {
    std::string blocked = "[";
    for (const PartContact& c : a.blocked_by) blocked += (blocked.size() > 1 ? ", " : "") + PartContactJson(c);
    attempts += (attempts.size() > 1 ? ",\n    " : "") + JsonWriter()
                                                             .Int("round", a.round)
                                                             .String("part", a.part)
                                                             .Bool("removable", a.removable)
                                                             .String("status_detail", a.status_detail)
                                                             .String("folder", a.folder)
                                                             .Int("waypoints", static_cast<long long>(a.waypoints))
                                                             .Number("seconds", a.seconds)
                                                             .Add("blocked_by", blocked + "]")
                                                             .Text();
  }
  std::string message;
  if (order.complete) {
    message = "every part comes out: " + std::to_string(order.steps.size()) + " step(s)";
  } else if (!order.cycle.empty()) {
    message = "no order exists: the parts left block each other in a cycle: ";
    for (std::size_t i = 0; i < order.cycle.size(); ++i) message += (i > 0 ? " -> " : "") + order.cycle[i];
  } else {
    message = "no order exists for the parts left (no part of them comes out within its budget)";
  }
  JsonWriter json;
  json.String("schema", "ausbau-order").Int("version", 1);
  json.String("producer", "ausbau-order").String("producer_version", AUSBAU_VERSION);
  json.Bool("complete", order.complete).Bool("order_exists", order.complete).String("message", message);
  json.Add("sequence", names(order.sequence)).Add("steps", steps + "]");
  json.Add("remaining", names(order.remaining)).Add("fixed", names(order.fixed));
  if (order.cycle.empty()) {
    json.Null("cycle");
  } else {
    json.Add("cycle", names(order.cycle));
  }
  json.Number("part_budget_seconds", options.part_budget_s)
      .String("validity", ValidityModeName(ValidityMode::kRigidExact));
  json.Add("attempts", attempts + "]");
  return json.Text() + "\n";
}

}  // namespace ausbau
