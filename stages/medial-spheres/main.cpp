// ausbau-medial-spheres: phase I of the deformability labeling (thesis 5.4.1,
// algorithm 9): one sphere per vertex of D, centred near the medial axis,
// whose radius is half the local thickness. The work is
// workflow/part_spheres.h; see README.md beside this file.
#include <string>

#include "artifact/run_files.h"
#include "cli/stage_options.h"
#include "workflow/part_spheres.h"

namespace ausbau {
namespace {

constexpr StageSpec kMedialSpheresStage{
    "ausbau-medial-spheres",
    "Computes one medial-axis sphere per vertex of the part D (deformability labeling, phase I).",
    SceneHash::kDynamicMesh,
    {kRunFileSpheres, kSpheresSchema, kSpheresSchemaVersion},
    {"D and options", "compute again"}};

struct SpheresStageOptions {
  std::string csv;
  std::string ply;
  PartSpheresOptions spheres;
};

// Only D's mesh file matters: S and the poses do not change the spheres.
void DeclareSpheres(StageDefinition& stage, SpheresStageOptions* options) {
  stage.ExtraOutput("--csv", &options->csv, "also write x,y,z,radius per vertex of D");
  stage.ExtraOutput("--ply", &options->ply, "also write D as PLY coloured by sphere radius");
  AddPartSpheresOptions(stage, &options->spheres);
}

// The spheres; the runner writes them, logs and writes --csv/--ply.
SpheresArtifact ComputeSpheres(const StageRun& run, const SpheresStageOptions& options) {
  return ComputePartSpheres(run.scene, options.spheres);
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kMedialSpheresStage, DeclareSpheres, ComputeSpheres,
                  PerVertexArtifact<SpheresArtifact>{WriteSpheresArtifact, ReadSpheresArtifact, WriteSpheresExtras})
