#include "collision/scene_parts.h"

#include <optional>

#include "core/error.h"
#include "core/format.h"
#include "scene/scene.h"
#include "scene/units.h"

namespace ausbau {

double RigidToleranceInSceneUnits(double millimetres, const std::string& units, bool* assumed) {
  const std::optional<double> per_unit = MillimetresPerUnit(units);
  if (assumed) *assumed = !per_unit.has_value();
  return per_unit ? millimetres / *per_unit : millimetres;
}

double RigidToleranceInSceneUnits(double millimetres, const Scene& scene, bool* assumed) {
  const double tolerance = RigidToleranceInSceneUnits(millimetres, scene.units, assumed);
  CheckStoredPrecision(scene, tolerance);
  return tolerance;
}

void CheckStoredPrecision(const Scene& scene, double tolerance) {
  if (!(scene.stored_spacing > tolerance / kStoredSpacingShare)) return;
  // A 9.7 mm opening 1e7 mm from the origin was stored as 10 mm and a
  // 10 mm cube passed it: no check can be exact on such coordinates.
  throw InputErrorAt(scene.stored_spacing_file.string(),
                     Fmt("coordinates reach %.6g, where single precision (the float32 of mesh files and of the "
                         "mesh reader) stores them only %.3g (scene units) apart, more than 1/%g of the rigid "
                         "tolerance (%.3g): move the model nearer the origin",
                         scene.stored_magnitude, scene.stored_spacing, kStoredSpacingShare, tolerance));
}

FitRule SceneFitRule(const Scene& scene) {
  FitRule rule;
  if (scene.fit_interference_mm)
    rule.max_depth = RigidToleranceInSceneUnits(*scene.fit_interference_mm, scene.units, nullptr);
  if (scene.tessellation_deflection_mm)
    rule.tessellation_depth = RigidToleranceInSceneUnits(*scene.tessellation_deflection_mm, scene.units, nullptr);
  return rule;
}

std::shared_ptr<const PartModel> ClassifySceneParts(const Scene& scene, double tolerance,
                                                    UnmeasuredInterference unmeasured) {
  CheckStoredPrecision(scene, tolerance);
  TriangleMesh robot = scene.dynamic_mesh;
  for (auto& v : robot.vertices) v -= scene.dynamic_origin;
  return ClassifyParts(robot, scene.static_mesh, scene.start, tolerance, unmeasured, SceneFitRule(scene));
}

}  // namespace ausbau
