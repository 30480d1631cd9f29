#include "workflow/scene_tau.h"

#include <cmath>

#include "collision/fcl_checker.h"
#include "core/error.h"
#include "core/log.h"
#include "inistate/inistate_planner.h"
#include "scene/units.h"

namespace ausbau {

void SceneTauOptions::Check() const {
  estimate.Check();
  if (!IsVolumeValidity(validity)) {
    throw InputError("--validity " + ValidityModeName(validity) + " has no tau; pick a volume mode");
  }
  if (!(psi >= 0) || !std::isfinite(psi)) throw OptionError(&psi, "psi", "must be >= 0");
}

TauArtifact EstimateSceneTau(const Scene& scene, const SceneTauOptions& options) {
  options.Check();
  const ValidityMode mode = options.validity;
  const PlanningProblem problem = MakePlanningProblem(scene);
  const std::unique_ptr<VolumeModel> model = LoadVolumeModel(scene, problem, mode, options.volume);
  const double psi = options.psi > 0 ? MillimetresInSceneUnits(options.psi, scene.units) : model->EstimatePsi();
  LogInfo("scene %s: validity %s, psi %.6g %s (%s), voxel %.4g %s", scene.name.c_str(), ValidityModeName(mode).c_str(),
          psi, scene.units.c_str(), options.psi > 0 ? "given" : "largest deformable component", model->voxel_size(),
          scene.units.c_str());

  TauArtifact artifact;
  artifact.validity = options.validity;
  artifact.units = scene.units;
  if (mode == ValidityMode::kShrink) {
    // Shrink plans with the shrunk D under plain collision: tau 0.
    artifact.estimate.psi = psi;
    artifact.estimate.solved = true;
    LogInfo("shrink: tau is 0 (D shrunk by %.4g %s)", model->shrink(), scene.units.c_str());
  } else {
    const FclCollisionChecker fcl(problem.robot, problem.environment);
    artifact.estimate =
        EstimateTau(FastenerProblem(problem, fcl, psi), model->volume(), model->measure(), psi, options.estimate);
  }
  return artifact;
}

}  // namespace ausbau
