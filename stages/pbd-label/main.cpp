// ausbau-pbd-label: phase II of the deformability labeling (thesis 5.4.1,
// algorithm 10): a position based dynamics simulation of D per load case
// (one per vertex, or a budget of them) gives each vertex of D a
// deformability in [0, 1]; or, where D is made of measured solids, the exact
// check's rule. The work is workflow/label_part.h; see README.md.
#include <string>

#include "cli/stage.h"
#include "core/log.h"
#include "labeling/pbd_label.h"
#include "workflow/label_part.h"

namespace ausbau {
namespace {

struct LabelStageOptions {
  std::string scene;
  std::string spheres;
  std::string output;
  std::string csv;
  std::string ply;
  LabelPartOptions label;
};

void WriteExtras(const LabelStageOptions& options, const Scene& scene, const LabelsArtifact& labels) {
  if (!options.csv.empty()) {
    WriteLabelsCsv(options.csv, scene.dynamic_mesh.vertices, labels.deformability);
    LogInfo("wrote %s", options.csv.c_str());
  }
  if (!options.ply.empty()) {
    WriteColoredPly(options.ply, scene.dynamic_mesh, labels.deformability, "deformability",
                    ColorRamp::kRigidToDeformable, 0.0, 1.0,
                    "ausbau-pbd-label: D coloured by deformability, blue rigid to red deformable");
    LogInfo("wrote %s", options.ply.c_str());
  }
}

int Label(const StageRun& run, const LabelStageOptions& options) {
  // D's content hash: hashed once, by the runner, for the provenance.
  std::string dynamic_hash;
  for (const auto& [role, hash] : run.provenance.inputs) {
    if (role == "dynamic") dynamic_hash = hash;
  }
  const LabelsArtifact artifact = LabelPart(run.scene, dynamic_hash, options.spheres, options.label);
  WriteLabelsArtifact(run.output, artifact, run.provenance);
  LogInfo("wrote %s (%zu vertices of D)", run.output.c_str(), artifact.deformability.size());
  WriteExtras(options, run.scene, artifact);
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  LabelStageOptions options;
  PbdLabelOptions& l = options.label.pbd;
  StageDefinition stage(
      "ausbau-pbd-label",
      "Labels each vertex of the part D with a deformability in [0, 1] by position based dynamics (phase II).");
  // S is an input too: the solid rule reads the installed intersections.
  stage.SceneInput(SceneHash::kWholeScene, &options.scene);
  stage.Option("--rule", &options.label.rule,
               "auto: by solids where D is made of closed solids whose installed intersections with S are measured, "
               "else PBD | solids | pbd (the thesis's simulation)",
               CacheKey::kYes);
  stage.Option("--rigid-tolerance", &options.label.rigid_tolerance_mm,
               "solid rule: a solid intersecting S deeper than this (mm) at the installed pose is a fastener",
               CacheKey::kYes);
  stage
      .InputArtifact("--spheres", &options.spheres, "spheres", kSpheresSchema, kSpheresSchemaVersion,
                     "spheres artifact of D (ausbau-medial-spheres)")
      ->required();
  stage.Output(&options.output, "labels.h5", kLabelsSchema, kLabelsSchemaVersion);
  stage.Option("--csv", &options.csv, "also write x,y,z,deformability per vertex of D", CacheKey::kNo);
  stage.Option("--ply", &options.ply, "also write D as PLY coloured by deformability (blue rigid, red deformable)",
               CacheKey::kNo);
  stage.Threads(&l.threads);
  stage.Option("--measure", &l.measure, "sum (thesis: displacements summed over all load cases) | self",
               CacheKey::kYes);
  stage.Option("--max-load-cases", &l.max_load_cases,
               "sum: load at most this many well-spread vertices, weighted by the area each stands for; 0 = every "
               "vertex",
               CacheKey::kYes);
  stage.Option("--kappa", &l.kappa, "load sigma = kappa x r_min", CacheKey::kYes);
  stage.Option("--density", &l.density, "rho in the scaled mesh; 0 = automatic (resolution-independent)",
               CacheKey::kYes);
  stage.Option("--time-step", &l.time_step, "seconds", CacheKey::kYes);
  stage.Option("--duration", &l.duration, "simulated seconds per load case", CacheKey::kYes);
  stage.Option("--solver-iterations", &l.solver_iterations, "solver iterations N per step", CacheKey::kYes);
  AddRenamedFlag(stage.app(), "--iterations", "--solver-iterations");
  stage.Option("--stiffness", &l.stiffness, "k", CacheKey::kYes);
  stage.Option("--stiffness-formula", &l.stiffness_formula, "thesis: k' = 1-(1-k)^N | mueller: k' = 1-(1-k)^(1/N)",
               CacheKey::kYes);
  stage.Option("--damping", &l.damping, "velocity factor per step", CacheKey::kYes);
  stage.Flag("!--no-bending", &l.bending, "no bending constraints", CacheKey::kYes);
  stage.Flag("!--no-thickness", &l.thickness, "masses without the sphere diameters (mean diameter)", CacheKey::kYes);
  stage.Flag("!--no-glue", &l.glue, "do not tie separate components that touch or overlap", CacheKey::kYes);
  stage.Option("--glue-tolerance", &l.glue_tolerance, "touching: closer than this fraction of D's diagonal",
               CacheKey::kYes);
  stage.Option("--refine", &l.refine, "split edges longer than this many local diameters; 0 = off", CacheKey::kYes);
  stage.Option("--weld-tolerance", &options.label.weld_tolerance,
               "weld vertices closer than this fraction of D's AABB diagonal", CacheKey::kYes);
  return stage.Run(
      argc, argv, [&](const StageRun& run) { return Label(run, options); },
      [&](const StageRun& run) {
        LogInfo("%s is up to date (same D, spheres and options); use --force to label again", run.output.c_str());
        WriteExtras(options, run.scene, ReadLabelsArtifact(run.output));
        return kExitOk;
      });
}
