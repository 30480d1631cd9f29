#include "cli/stage_options.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/hash.h"

namespace ausbau {

TimeBudgetOptions::TimeBudgetOptions()
    : started(std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count()) {}

double TimeBudgetOptions::Deadline() const {
  double end = deadline;
  if (budget_s > 0 && (end <= 0 || started + budget_s < end)) end = started + budget_s;
  return end;
}

void AddTimeBudgetOptions(StageDefinition& stage, TimeBudgetOptions* budget) {
  stage
      .Option("--budget", &budget->budget_s,
              "seconds this run may take: the work stops when they are used up (the best result so far is written; "
              "0 = none)",
              CacheKey::kNo)
      ->check(Within(0, 7 * 24 * 3600.0));
  stage
      .Option("--deadline", &budget->deadline,
              "the same as an absolute time, seconds since the Unix epoch (the pipeline's BUDGET; 0 = none)",
              CacheKey::kNo)
      ->check(Within(0, 1e11));
}

void AddPlannerOptions(StageDefinition& stage, PlannerOptions* planner) {
  stage.Option("--planner", &planner->planner,
               "rrt | rrtc | cr-rrtc | est | prm; auto = cr-rrtc, or est for sigma_1 in volume modes", CacheKey::kYes);
  stage.Option("--sampler", &planner->sampler, "uniform | gaussian | bridge | mixed", CacheKey::kYes);
  stage.Option("--sigma", &planner->sampler_sigma,
               "gaussian/bridge deviation as a fraction of D's diagonal; 0 = automatic (0.25)", CacheKey::kYes);
  stage.Threads(&planner->threads);
  stage.Seed(&planner->seed);
  stage
      .Option("--time-limit", &planner->time_limit_s,
              "seconds: a safety net (the work is counted: restarts after 4096, 8192, ... iterations, crop levels "
              "by --crop-level-iterations); a search it stops is marked cut short (stopped_by_budget: the verdict "
              "says not-removable (budget))",
              CacheKey::kYes)
      ->check(TimeLimit());
  stage.Option("--max-iterations", &planner->max_iterations,
               "one run of at most this many iterations, no restarts; 0 = unlimited", CacheKey::kYes);
  stage.Option("--u", &planner->u, "rrtc: metric weight of translation, (0, 1)", CacheKey::kYes);
  stage.Option("--range-max", &planner->range_max, "rrtc: maximal edge range, (0, 1]", CacheKey::kYes);
  stage.Option("--resolution", &planner->resolution,
               "the search's edge check step as a fraction of D's AABB diagonal (the path is certified at a quarter "
               "of it, and at most 0.0025)",
               CacheKey::kYes);
  stage.Option("--passage-neighbors", &planner->passage_neighbors,
               "rrtc, cr-rrtc: a trapped extension is tried once more along the principal directions of this many "
               "nearby tree nodes (narrow passages; docs/planning.md); 0 = off",
               CacheKey::kYes);
  planner->coarse_iterations = -1;  // automatic: ResolvedPlanner (workflow/plan_scene.cpp) decides by the validity
  stage.Option(
      "--coarse-iterations", &planner->coarse_iterations,
      "rrtc, cr-rrtc: a first search at a step of 4% of D's diagonal for at most this many iterations; "
      "without a path it can certify, the search at --resolution starts afresh (docs/planning.md, \"A "
      "coarse search first\"); 0 = off; -1 = automatic: 4096 for rrtc and cr-rrtc with --validity collision, else 0",
      CacheKey::kYes);
  stage.Option("--pull-legs", &planner->pull_legs,
               "disassembly: straight pulls from the installed pose before sampling, 1 = single pulls only, 2 = "
               "also two legs where none is free, and the sampling tree grown from where they stopped too "
               "(docs/rigid-exact.md, \"Two legs, and where the pulls stopped\")",
               CacheKey::kYes);
  planner->exit_axes = -1;  // automatic: ResolvedPlanner (workflow/plan_scene.cpp) decides by the validity
  stage.Option("--exit-axes", &planner->exit_axes,
               "rrtc, cr-rrtc, disassembly: from each new start-tree node, straight pulls out of S along this many "
               "of D's surface-normal axes (largest first) and quarter turns about them (docs/planning.md, \"Exit "
               "moves\"); 0 = off, at most 3; -1 = automatic: 1 with --validity collision, else 0",
               CacheKey::kYes);
}

void AddVolumeInputOptions(StageDefinition& stage, VolumeInputs* volume) {
  stage.InputFile("--voxels", &volume->voxels, "voxels",
                  "volume modes: voxels of S and D (ausbau-voxelize); default: voxelized here");
  stage.InputFile("--labels", &volume->labels, "labels", "labels of D (ausbau-pbd-label); needed by the labeled modes");
  stage.Option("--rigid-tolerance", &volume->rigid_tolerance_mm,
               "rigid-exact, and labeled-mliv's rigid guard: how deep D's rigid part may touch into S, in mm "
               "(converted by the scene's units)",
               CacheKey::kYes);
}

namespace {

// --clearance, the same for planning and smoothing.
void AddClearanceOption(StageDefinition& stage, double* clearance) {
  stage
      .Option("--clearance", clearance,
              "distance from S to keep where the path allows, mm (converted by the scene's units; a preference, never "
              "at the cost of "
              "validity; where a passage is narrower the verdict says where); -1: 0.5 mm in the scene's units, "
              "kept by smoothing only (ausbau-plan keeps a clearance only when one is given); 0: none",
              CacheKey::kYes)
      ->check([](const std::string& text) -> std::string {
        try {
          const double value = std::stod(text);
          if (value == -1 || (value >= 0 && std::isfinite(value))) return "";
        } catch (const std::exception&) {
        }
        return "must be a number >= 0 (scene units), or -1 for the default";
      });
}

}  // namespace

void AddPlanSceneOptions(StageDefinition& stage, PlanSceneOptions* plan) {
  AddPlannerOptions(stage, &plan->planner);
  stage.Choice("--collision", &plan->collision, CollisionModeNames(), ParseCollisionMode, CollisionModeName,
               "fcl | farr (FARR rays in front of FCL, same answers; docs/farr.md)", CacheKey::kYes);
  stage.Choice("--validity", &plan->validity, ValidityModeNames(), ParseValidityMode, ValidityModeName,
               "rigid-exact | collision | shrink | iv | mliv | labeled-mliv | labeled-mliv-unguarded (all but "
               "collision: the start may collide; docs/inistate.md, docs/rigid-exact.md)",
               CacheKey::kYes);
  AddVolumeInputOptions(stage, &plan->volume);
  stage.app()
      .add_option("--tau", plan->tau,
                  "volume threshold, scene units^3; default: from --tau-file, else estimated (shrink: 0)")
      ->check(NonNegative());
  stage.InputFile("--tau-file", &plan->tau_file, "tau", "tau and psi from ausbau-tau-estimate (HDF5)");
  stage.app().add_option(
      "--psi", plan->psi,
      "sigma_1 ends when distance(S, D) > psi, mm (converted by the scene's units); default: from --tau-file "
      "or the labels");
  stage
      .Option("--max-crop-level", &plan->max_crop_level,
              "rigid-exact on a large S: how often the crop around D may double when no path is found "
              "(README: cropping S to D's reach); -1: until it holds all of S",
              CacheKey::kYes)
      ->check(CLI::Range(-1, 1000));
  stage
      .Option("--crop-level-iterations", &plan->crop_level_iterations,
              "rigid-exact: planner iterations (restarts together) a crop level gets before the crop grows; the "
              "last level has no cap. Work, not seconds, so the answer is the same at any load (default: four "
              "restart rounds, about what a share of 60 s over 3-5 levels did on a 2-core machine)",
              CacheKey::kYes)
      ->check(Within(1, 1e6));
  stage.Option("--rigid-planner", &plan->rigid_planner, "planner of sigma_2 (volume modes), collision-checked",
               CacheKey::kYes);
  stage.Option("--distfield", &plan->distfield,
               "farr: distance fields S.h5,D.h5 (ausbau-distfield-build); default: built or reused through the "
               "cache (<scene dir>/.ausbau-cache or $AUSBAU_CACHE_DIR)",
               CacheKey::kNo);
  // The two distance-field files: inputs (one option names both), split
  // as written whatever --collision says, and hashed by content.
  stage.InputPaths("--distfield", [plan] {
    std::vector<std::string> files;
    std::size_t begin = 0;
    while (begin <= plan->distfield.size()) {
      const std::size_t comma = std::min(plan->distfield.find(',', begin), plan->distfield.size());
      if (comma > begin) files.push_back(plan->distfield.substr(begin, comma - begin));
      begin = comma + 1;
    }
    return files;
  });
  stage.AddInputs([plan](Provenance* provenance) {
    const std::vector<std::string> distfield = DistfieldPaths(*plan);
    if (distfield.empty()) return;
    provenance->inputs.emplace_back("distfield-static", HashFile(distfield[0]));
    provenance->inputs.emplace_back("distfield-dynamic", HashFile(distfield[1]));
  });
  stage.Flag("!--no-verify", &plan->verify, "skip the dense re-check of the result", CacheKey::kNo);
  AddClearanceOption(stage, &plan->clearance);
}

void AddSmoothOptions(StageDefinition& stage, SmoothOptions* smooth) {
  stage.Seed(&smooth->seed);
  stage.Option("--attempts", &smooth->attempts, "shortcut attempts, 0 = automatic", CacheKey::kYes);
  stage
      .Option("--time-limit", &smooth->time_limit_s,
              "seconds: a safety net (the work is counted: --attempts shortcuts, a quarter of them partial, 20000 "
              "iterations for the translation-only alternative); smoothing it stops keeps the valid path so far and "
              "is marked cut short (smoothing_cut_short in the verdict)",
              CacheKey::kYes)
      ->check(TimeLimit());
  stage.Option("--resolution", &smooth->resolution, "edge check step as a fraction of D's AABB diagonal",
               CacheKey::kYes);
  AddClearanceOption(stage, &smooth->clearance);
}

void AddTauEstimateOptions(StageDefinition& stage, TauEstimateOptions* estimate) {
  stage.Seed(&estimate->planner.seed);
  stage
      .Option("--time-limit", &estimate->planner.time_limit_s,
              "seconds per planning round: a safety net only (a round it stops makes the estimate cut short, which "
              "the verdict records); --round-checks sets the work",
              CacheKey::kYes)
      ->check(TimeLimit());
  stage
      .Option("--round-checks", &estimate->round_checks,
              "validity checks per planning round: a round that has not found sigma_1 after them has failed. Work, "
              "not seconds, so that tau is the same at any load (default 40000, 20 reference seconds: the clip "
              "scenes' successful rounds need up to 25000; a failed one takes 15-25 s on one core here)",
              CacheKey::kYes)
      ->check(Within(1, 1e12));
  stage.Option("--planner", &estimate->planner.planner, "local planner of sigma_1 (est, rrt, cr-rrtc, ...)",
               CacheKey::kYes);
  stage.Option("--initial-speed", &estimate->initial_speed, "s_init, nodes per reference second", CacheKey::kYes);
  stage.Option("--speed-step", &estimate->speed_step, "delta_2: target speed increase after a failed round",
               CacheKey::kYes);
  stage.Option("--rounds", &estimate->max_rounds, "planning rounds at most", CacheKey::kYes);
  stage.Option("--probe-attempts", &estimate->probe_attempts, "expansion attempts per speed probe", CacheKey::kYes);
  stage.Threads(&estimate->threads);
}

void AddPartSpheresOptions(StageDefinition& stage, PartSpheresOptions* options) {
  MedialSphereOptions* spheres = &options->spheres;
  stage.Threads(&spheres->threads);
  stage.Option("--delta", &spheres->delta, "start offset inside, fraction of D's AABB diagonal", CacheKey::kYes);
  stage.Option("--push-factor", &spheres->step, "push factor eps while growing, in (0, 1)", CacheKey::kYes);
  stage.Option("--cooling-iterations", &spheres->cooling_iterations,
               "cooling iterations (eps falls linearly to push factor / iterations)", CacheKey::kYes);
  stage.Option("--growth-iterations", &spheres->growth_iterations,
               "at most this many iterations at eps = push factor while the sphere grows; 0 = cool from the start",
               CacheKey::kYes);
  AddRenamedFlag(stage.app(), "--step", "--push-factor");
  AddRenamedFlag(stage.app(), "--iterations", "--cooling-iterations");
  stage.Option("--weld-tolerance", &options->weld_tolerance,
               "weld vertices closer than this fraction of D's AABB diagonal", CacheKey::kYes);
}

void AddLabelPartOptions(StageDefinition& stage, LabelPartOptions* label) {
  PbdLabelOptions& pbd = label->pbd;
  stage.Option("--rule", &label->rule,
               "auto: by solids where D is made of closed solids whose installed intersections with S are measured, "
               "else PBD | solids | pbd (the thesis's simulation)",
               CacheKey::kYes);
  stage.Option("--rigid-tolerance", &label->rigid_tolerance_mm,
               "solid rule: a solid intersecting S deeper than this (mm) at the installed pose is a fastener",
               CacheKey::kYes);
  stage.Threads(&pbd.threads);
  stage.Option("--measure", &pbd.measure, "sum (thesis: displacements summed over all load cases) | self",
               CacheKey::kYes);
  stage.Option("--max-load-cases", &pbd.max_load_cases,
               "sum: load at most this many well-spread vertices, weighted by the area each stands for; 0 = every "
               "vertex",
               CacheKey::kYes);
  stage.Option("--kappa", &pbd.kappa, "load sigma = kappa x r_min", CacheKey::kYes);
  stage.Option("--density", &pbd.density, "rho in the scaled mesh; 0 = automatic (resolution-independent)",
               CacheKey::kYes);
  stage.Option("--time-step", &pbd.time_step, "seconds", CacheKey::kYes);
  stage.Option("--duration", &pbd.duration, "simulated seconds per load case", CacheKey::kYes);
  stage.Option("--solver-iterations", &pbd.solver_iterations, "solver iterations N per step", CacheKey::kYes);
  AddRenamedFlag(stage.app(), "--iterations", "--solver-iterations");
  stage.Option("--stiffness", &pbd.stiffness, "k", CacheKey::kYes);
  stage.Option("--stiffness-formula", &pbd.stiffness_formula, "thesis: k' = 1-(1-k)^N | mueller: k' = 1-(1-k)^(1/N)",
               CacheKey::kYes);
  stage.Option("--damping", &pbd.damping, "velocity factor per step", CacheKey::kYes);
  stage.Flag("!--no-bending", &pbd.bending, "no bending constraints", CacheKey::kYes);
  stage.Flag("!--no-thickness", &pbd.thickness, "masses without the sphere diameters (mean diameter)", CacheKey::kYes);
  stage.Flag("!--no-glue", &pbd.glue, "do not tie separate components that touch or overlap", CacheKey::kYes);
  stage.Option("--glue-tolerance", &pbd.glue_tolerance, "touching: closer than this fraction of D's diagonal",
               CacheKey::kYes);
  stage.Option("--refine", &pbd.refine, "split edges longer than this many local diameters; 0 = off", CacheKey::kYes);
  stage.Option("--weld-tolerance", &label->weld_tolerance,
               "weld vertices closer than this fraction of D's AABB diagonal", CacheKey::kYes);
}

}  // namespace ausbau
