// ausbau-pbd-label: phase II of the deformability labeling (thesis 5.4.1,
// algorithm 10): a position based dynamics simulation of D per load case
// (one per vertex, or a budget of them) gives each vertex of D a
// deformability in [0, 1]; or, where D is made of measured solids, the exact
// check's rule. The work is workflow/label_part.h; see README.md.
#include <string>

#include "artifact/run_files.h"
#include "cli/stage_options.h"
#include "labeling/pbd_label.h"
#include "workflow/label_part.h"

namespace ausbau {
namespace {

constexpr StageSpec kPbdLabelStage{
    "ausbau-pbd-label",
    "Labels each vertex of the part D with a deformability in [0, 1] by position based dynamics (phase II).",
    SceneHash::kWholeScene,
    {kRunFileLabels, kLabelsSchema, kLabelsSchemaVersion},
    {"D, spheres and options", "label again"}};

struct LabelStageOptions {
  std::string spheres;
  std::string csv;
  std::string ply;
  LabelPartOptions label;
};

// S is an input too: the solid rule reads the installed intersections.
void DeclareLabel(StageDefinition& stage, LabelStageOptions* options) {
  stage
      .InputArtifact("--spheres", &options->spheres, "spheres", kSpheresSchema, kSpheresSchemaVersion,
                     "spheres artifact of D (ausbau-medial-spheres)")
      ->required();
  stage.ExtraOutput("--csv", &options->csv, "also write x,y,z,deformability per vertex of D");
  stage.ExtraOutput("--ply", &options->ply,
                    "also write D as PLY coloured by deformability (blue rigid, red deformable)");
  AddLabelPartOptions(stage, &options->label);
}

// The labels (D's content hash: hashed once, by the runner, for the
// provenance); the runner writes them, logs and writes --csv/--ply.
LabelsArtifact Label(const StageRun& run, const LabelStageOptions& options) {
  return LabelPart(run.scene, run.DynamicMeshHash(), options.spheres, options.label);
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kPbdLabelStage, DeclareLabel, Label,
                  PerVertexArtifact<LabelsArtifact>{WriteLabelsArtifact, ReadLabelsArtifact, WriteLabelsExtras})
