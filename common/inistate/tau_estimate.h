// Automatic threshold tau for InIState planning (thesis 5.4.5).
//
// tau starts at tau_lowest, the volume of the installed pose (below it the
// start itself is invalid), and is raised until the local planner's tree
// grows at the target expansion speed s (s_init = 4 nodes per second). Then
// a planning round (sigma_1 only) runs with that tau; if it fails, the
// target speed rises by delta_2 = 5 nodes/s and tau is raised again, to at
// least twice its distance from tau_lowest (plus two voxels): the speed may
// already exceed the new target at the failed tau.
//
// Expansion speed, made deterministic: the thesis counts nodes per second of
// wall-clock time, which would make tau (and so the path) depend on the
// machine and its load. We count time in validity checks instead: one
// reference second is kChecksPerReferenceSecond checks (about what the
// thesis's 4-core machine did per second with its Labeled-MLIV; ours does
// 10-20k per second per core on the clip scenes), so s = nodes added per
// 1000 checks x (kChecksPerReferenceSecond / 1000). A probe grows the tree
// from the start for a fixed number of expansion attempts.
//
// The search: candidates tau_lowest + delta (2^k - 1), delta = one voxel of
// D, k = 0, 1, ..., probed `threads` at a time in parallel (probes are
// independent and seeded alike, so the result does not depend on the thread
// count); the first candidate whose speed reaches the target is refined by
// bisection against the one before (the speed grows with tau).
//
// Two lanes: a round's tau depends only on the probes and on the rounds
// before it having failed, and a failed round costs its whole iteration
// budget on one core (the local planner is sequential). So while one lane plans round
// r, the other searches round r + 1's tau as if r had failed and plans it;
// when r succeeds, the other lane is cancelled (PlannerOptions::cancel) and
// its probes and round are left out of the trace. The result is the
// one-round-at-a-time result (tested); on clips-ds5 seed 1 (four failed
// rounds of 10 s) the estimate takes 28 s instead of 49 s on 2 cores. One
// thread: one lane.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "inistate/intersection_volume.h"
#include "planning/planner.h"
#include "planning/validity_mode.h"

namespace ausbau {

inline constexpr double kChecksPerReferenceSecond = 2000.0;
inline constexpr std::int64_t kDefaultTauRoundChecks = 40000;

struct TauEstimateOptions {
  double initial_speed = 4.0;         // s_init, nodes per reference second
  double speed_step = 5.0;            // delta_2
  int max_rounds = 5;                 // planning rounds
  std::int64_t probe_attempts = 300;  // expansion attempts per probe
  int bisection_steps = 4;
  double max_tau = 0;  // 0 = D's whole volume (IV of all of D)
  // Local planner (est) and seed. A planning round ends when sigma_1 is
  // found or after round_checks validity checks (work, counted as the
  // probes' speed is, so that which round succeeds, hence tau and the path,
  // is the same at any load); planner.time_limit_s is only a safety net per
  // round (--time-limit): a round it stops, or a round the deadline keeps
  // from starting, makes the estimate cut_short.
  PlannerOptions planner;
  // 40000 checks, 20 reference seconds (kChecksPerReferenceSecond): the
  // clip scenes' successful rounds need 170-25000 checks (clips-ds5 seed 3:
  // 24501, which its old 10 s of wall time allowed on an idle machine); a
  // failed round costs 15-25 s at the 1600-2500 checks a second one core
  // does here. Checks, not iterations: an EST iteration costs 1 to 14
  // checks from scene to scene, a check about the same everywhere.
  std::int64_t round_checks = kDefaultTauRoundChecks;
  int threads = 0;  // parallel probes; 0 = all cores
  // The run's time budget (planning/planner.h: SecondsLeft; 0: none): each
  // planning round gets at most what is left, and no round starts after it.
  double deadline = 0;
  // 60 s per round: a safety net well above the 0.1-25 s a round of
  // round_checks takes here, so that it fires only on a machine several
  // times slower (then the estimate says it was cut short).
  TauEstimateOptions() {
    planner.planner = "est";
    planner.time_limit_s = 60.0;
  }
  void Check() const;  // throws InputError
};

struct TauProbe {
  int round = 0;            // planning round this probe belongs to (0-based)
  double target_speed = 0;  // nodes per reference second
  double tau = 0;
  double speed = 0;  // measured; infinite when the probe reached the goal
  std::int64_t nodes = 0, attempts = 0, checks = 0;
  bool planning_round = false;  // a full planning round rather than a probe
  bool solved = false;          // planning round: sigma_1 found
  double seconds = 0;
};

struct TauEstimate {
  double tau = 0;         // the estimate (the last round's tau)
  double tau_lowest = 0;  // volume at the installed pose
  double psi = 0;
  double speed_target = 0;  // of the last round
  int rounds = 0;
  bool solved = false;  // the last planning round found sigma_1
  std::vector<TauProbe> trace;
  double seconds = 0;
  std::vector<Pose> local_path;  // sigma_1 of the successful round (planning convention)
  std::uint64_t local_seed = 0;  // the planner seed that round used
  std::string local_planner;     // and its planner
  // The clock (a round's --time-limit or the run's deadline) stopped a
  // round or kept one from starting: not the deterministic estimate.
  bool cut_short = false;
};

// `problem` must carry the goal test of sigma_1 (ClearOfFasteners);
// `volume` is the mode's intersection volume (measure as given).
TauEstimate EstimateTau(const PlanningProblem& problem, const IntersectionVolume& volume, VolumeMeasure measure,
                        double psi, const TauEstimateOptions& options);

// ---- the `ausbau-tau` artifact (schemas/tau.md)
inline constexpr char kTauSchema[] = "ausbau-tau";
inline constexpr int kTauSchemaVersion = 1;

struct TauArtifact {
  TauEstimate estimate;
  ValidityMode validity = ValidityMode::kLabeledMliv;  // the volume mode the estimate is for
  std::string units;
};
void WriteTauArtifact(const std::filesystem::path& file, const TauArtifact& tau, const Provenance& provenance);
TauArtifact ReadTauArtifact(const std::filesystem::path& file);
// The trace as CSV (round,target_speed,tau,speed,nodes,attempts,checks,planning_round,solved,seconds).
void WriteTauTraceCsv(const std::filesystem::path& file, const TauEstimate& estimate);

}  // namespace ausbau
