// ausbau-verdict's work: the answer of a run for one scene. Is D removable
// (the path found, and its file passing the independent exact check), where
// along the path is the largest (Labeled-)MLIV, what blocks D where it is
// not removable, how long did the stages take: verdict.json
// (schemas/verdict.md) and a short summary for people.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "collision/part_contacts.h"
#include "inistate/tau_estimate.h"
#include "planning/exact_check.h"
#include "planning/path_io.h"
#include "scene/scene.h"
#include "workflow/path_quality.h"

namespace ausbau {

inline constexpr char kVerdictSchema[] = "ausbau-verdict";
inline constexpr int kVerdictSchemaVersion = 1;

struct VerdictInputs {
  std::string path;    // the final path artifact (ausbau-path)
  std::string csv;     // the path's CSV as written; empty: the artifact's waypoints are checked
  std::string tau;     // tau artifact (ausbau-tau-estimate); optional
  std::string times;   // folder of <stage>.seconds files (scripts/timed.sh); optional
  double budget = -1;  // seconds; < 0: none
  double rigid_tolerance_mm = 0.05;
  // The exact check's segments checked (core/log.h); empty = silent.
  ProgressCallback progress;
};

// The waypoint with the largest volume (volume modes).
struct MaxVolume {
  double value = 0;
  int index = 0;
  int part = -1;
  double deformability = 0;
  bool in_sigma_1 = false;
};

struct Verdict {
  VerdictInputs inputs;
  std::string scene_name, scene_file, units;
  PathArtifact path;
  std::optional<TauArtifact> tau;
  std::vector<std::pair<std::string, double>> stage_seconds;  // pipeline order
  double total_seconds = 0;
  double tolerance = 0;  // scene units
  std::optional<ExactCheckReport> exact;
  std::optional<BlockingReport> blocking;  // not removable: what holds D
  std::optional<MaxVolume> max_volume;
  std::optional<PathQuality> quality;   // with a path: its lengths and clearance (workflow/path_quality.h)
  double tau_value = 0, psi_value = 0;  // NaN where none
  bool removable = false;
  // The path is one waypoint: D already in its goal (clear of S) at the
  // installed pose, judged as staying there (removable without a motion).
  bool already_in_goal = false;
  // Not removable: the time budget ended the search (the path artifact's
  // stopped_by_budget): "not-removable (budget)".
  bool stopped_by_budget = false;
  // Not removable: where D got to (the best partial path's last pose where
  // counted work ended the search, else the installed pose: never a pose
  // the clock chose; scene convention) and what of S is there: the parts
  // D intersects or comes within reach of (collision/part_contacts.h).
  Pose blocked_at;
  bool blocked_at_partial_end = false;
  std::vector<PartContact> blockers;
  // Not removable, S of several parts: a part of S that stopped a
  // straight pull (what_blocks) and is none of D's contacts above (a rod
  // over a bolt's head: the bolt slides in its bore until the rod stops
  // it; FindPullStopper), and whether D comes out along a straight pull
  // without it. Empty where no such part.
  std::string pull_stopper;
  bool pull_stopper_frees = false;
};

// "removable", "not-removable (budget)", "not-removable (no path)" or
// "not-removable (exact check failed)": the status with its reason.
std::string VerdictStatusDetail(const Verdict& verdict);

// Where to ask what blocks a D that was not removed: the end of the
// search's best partial path where counted work ended the search (the same
// end on any machine), else the installed pose (scene convention). Never
// the end of a search the clock stopped: how far it got depends on the
// machine and its load (docs/pipelines.md, "Work budgets").
bool BlockedAtPartialEnd(const PathArtifact& path);
Pose WhereBlocked(const PathArtifact& path, const Scene& scene);

// The parts of S at `pose` of D (scene convention): those D intersects or
// comes within 5% of its AABB diagonal of, at most 8, at least the nearest
// part. Where S has several parts, each is also taken away alone and D
// pulled straight out of the rest (ProbeWhatBlocks, exact check with
// `tolerance`, scene units): the parts whose removal frees D
// (PartContact::frees) come first, then deepest contact, then nearest.
std::vector<PartContact> FindBlockingParts(const Scene& scene, const Pose& pose, double tolerance,
                                           UnmeasuredInterference unmeasured = UnmeasuredInterference::kRigid);

// Of the parts of S that stopped D's blocked straight pulls (`pulls`,
// ProbeWhatBlocks from the installed pose) and are none of `contacts`
// (FindBlockingParts, already taken away there), the first, farthest pull
// first, whose removal alone lets D out along a straight pull (frees), else
// the farthest pull's (frees false); none where no such part. A post under
// a cap touches only its base: its pull up slides to the cap, and without
// the cap it comes out. Each part tried costs a ProbeWhatBlocks of S
// without it (work, not seconds).
struct PullStopper {
  int part = -1;  // index of static_part_names
  std::string name;
  bool frees = false;
};
std::optional<PullStopper> FindPullStopper(const Scene& scene, const BlockingReport& pulls,
                                           const std::vector<PartContact>& contacts, double tolerance,
                                           UnmeasuredInterference unmeasured = UnmeasuredInterference::kRigid);

// `scene` with part `part` of S (an index of static_part_names) taken out.
Scene WithoutStaticPart(const Scene& scene, int part);

// One entry of verdict.json's blocked_by.parts (and order.json's): part,
// index, intersects, depth or distance, point.
std::string PartContactJson(const PartContact& contact);

// Reads the inputs and judges. Throws InputError naming the file for inputs
// that do not fit (another scene's path, a malformed times folder).
Verdict JudgeRun(const Scene& scene, const VerdictInputs& inputs);

// verdict.json's text (schemas/verdict.md).
std::string VerdictJson(const Verdict& verdict);

// The summary for people: REMOVABLE / NOT REMOVABLE and the lines behind it.
void PrintVerdictSummary(const Verdict& verdict, const std::string& verdict_file, std::FILE* out);

}  // namespace ausbau
