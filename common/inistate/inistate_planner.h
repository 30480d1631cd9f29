// The InIState motion planner (thesis 5.4.4): D starts in collision with S
// (relaxed clips). Two parts:
//   sigma_1  from the installed pose under a volume validity (Labeled-MLIV
//            <= tau, or another mode) with the goal distance(S, D) > psi,
//            psi the extent of the largest fastening element: once D is that
//            far from S the clips no longer matter. The default planner is
//            EST, which samples locally around its tree and so finds the
//            narrow passage near the start (other planners selectable);
//   sigma_2  from that intermediate pose c_inter, a rigid planner (CR-RRTC by
//            default) under collision detection (FCL or FARR) into the
//            disassembly region (or to the goal pose).
// The joined path is sigma_1 followed by sigma_2 without c_inter's repeat.
#pragma once

#include <functional>
#include <vector>

#include "planning/planner.h"

namespace ausbau {

class FclCollisionChecker;

struct InIStateOptions {
  PlannerOptions local;  // sigma_1; planner "est" by default
  PlannerOptions rigid;  // sigma_2; planner "cr-rrtc" by default
  double psi = 0;        // scene units; > 0
  // A sigma_1 found before under the same validity (ausbau-tau-estimate's
  // successful round, planning convention), or empty. It is used instead of
  // planning sigma_1 if it holds here: it starts at the start, every segment
  // passes the volume validity at the planner's certification step
  // (local.resolution / 4 of D's diagonal) and it ends clear of the
  // fasteners; otherwise sigma_1 is planned as usual.
  std::vector<Pose> known_local_path;
  InIStateOptions() { local.planner = "est"; }
};

struct InIStateResult {
  PlanStatus status = PlanStatus::kTimeLimit;
  std::vector<Pose> path;  // planning convention; empty unless solved
  int inter_index = -1;    // index of c_inter in path
  PlanResult local, rigid;
  bool solved() const { return status == PlanStatus::kSolved; }
  PlanStats Stats() const;  // both parts together
};

// `volume_validity` checks sigma_1 (the start must be valid under it),
// `rigid_validity` sigma_2; `distance` returns distance(S, D) at a pose (0 in
// collision) and `colliding` tells whether D touches S (cheap pre-test of
// the goal). Deterministic for a seed unless a time limit ends a part.
InIStateResult PlanInIState(const PlanningProblem& problem, const PoseValidity& volume_validity,
                            const PoseValidity& rigid_validity, const std::function<bool(const Pose&)>& colliding,
                            const std::function<double(const Pose&)>& distance, const InIStateOptions& options);

// The same with the goal's tests done by FCL on D and S (`fcl`).
InIStateResult PlanInIState(const PlanningProblem& problem, const PoseValidity& volume_validity,
                            const PoseValidity& rigid_validity, const FclCollisionChecker& fcl,
                            const InIStateOptions& options);

// The problem sigma_1 solves (and the tau estimate probes): `problem`
// without a goal pose, its goal region D clear of the fasteners
// (ClearOfFasteners, tested by `fcl`). `problem` and `fcl` must outlive it.
PlanningProblem FastenerProblem(const PlanningProblem& problem, const FclCollisionChecker& fcl, double psi);

// The options of sigma_1's planner: EST's expansion radius, when automatic,
// becomes psi / nu: the tree advances at most one fastener length (and turns
// by at most 2 pi psi / nu) per step, so that it feels its way through the
// narrow passage at the installed pose rather than jumping across it (the
// thesis's "small sphere around the data structure"). Measured on the
// clips-ds* scenes (seed 1): with the rigid planners' radius (a quarter of
// D's diagonal) sigma_1 leaves in 2-3 giant steps and rigid parts clip S on
// ds1-ds3; with psi / nu, ds1 becomes correct.
PlannerOptions LocalPlannerOptions(const PlanningProblem& problem, double psi, PlannerOptions local);

// The goal of sigma_1: D's AABB more than psi away from S's, or D free of S
// and more than psi from it.
std::function<bool(const Pose&)> ClearOfFasteners(const PlanningProblem& problem,
                                                  std::function<bool(const Pose&)> colliding,
                                                  std::function<double(const Pose&)> distance, double psi);

}  // namespace ausbau
