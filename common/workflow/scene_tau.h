// ausbau-tau-estimate's work: the volume threshold tau (thesis 5.4.5) and
// psi (5.4.4) of one scene, for one volume validity mode, from its voxels
// and labels.
#pragma once

#include <string>

#include "inistate/tau_estimate.h"
#include "scene/scene.h"
#include "workflow/volume_inputs.h"

namespace ausbau {

struct SceneTauOptions {
  ValidityMode validity = ValidityMode::kLabeledMliv;  // a volume mode (shrink | iv | mliv | labeled-mliv | ...)
  double psi = 0;  // mm (--psi; converted by the scene's units); 0 = from the labels (largest deformable component)
  VolumeInputs volume;
  TauEstimateOptions estimate;
  // Throws InputError naming the flag of a value that does not fit.
  void Check() const;
};

// Shrink: tau 0 (D shrunk, plain collision). Otherwise the thesis's search;
// estimate.solved says whether a planning round found sigma_1.
TauArtifact EstimateSceneTau(const Scene& scene, const SceneTauOptions& options);

}  // namespace ausbau
