#include "workflow/label_part.h"

#include <omp.h>

#include <cmath>
#include <optional>

#include "collision/scene_parts.h"
#include "core/error.h"
#include "core/log.h"
#include "labeling/solid_labels.h"

namespace ausbau {

void LabelPartOptions::Check() const {
  pbd.Check();
  if (rule != "auto" && rule != "solids" && rule != "pbd") {
    throw OptionError(&rule, "rule", "expected auto, solids or pbd, got '" + rule + "'");
  }
  if (!(rigid_tolerance_mm > 0 && std::isfinite(rigid_tolerance_mm))) {
    throw OptionError(&rigid_tolerance_mm, "rigid_tolerance", "must be a positive number of millimetres");
  }
  if (!(weld_tolerance >= 0 && weld_tolerance < 1)) {
    throw OptionError(&weld_tolerance, "weld_tolerance", "must lie in [0, 1) (a fraction of D's AABB diagonal)");
  }
}

LabelsArtifact LabelPart(const Scene& scene, const std::string& dynamic_hash, const std::string& spheres_file,
                         const LabelPartOptions& options) {
  options.Check();
  // The spheres must belong to this D: their inputs hold D's content hash.
  SpheresArtifact spheres = ReadSpheresArtifact(spheres_file);
  if (ArtifactReader(spheres_file, kSpheresSchema, kSpheresSchemaVersion)
          .ReadStringAttribute("", "inputs")
          .find(dynamic_hash) == std::string::npos) {
    throw InputErrorAt(spheres_file, "computed for another part D (" + scene.dynamic_file.string() +
                                         " has different content); run ausbau-medial-spheres on this scene");
  }

  if (options.rule != "pbd") {
    bool assumed = false;
    const double tolerance = RigidToleranceInSceneUnits(options.rigid_tolerance_mm, scene, &assumed);
    const SolidLabels solids = LabelBySolids(scene, tolerance);
    if (solids.applies) {
      LogInfo("labels by solids: %s", solids.reason.c_str());
      LabelsArtifact artifact;
      artifact.deformability = solids.deformability;
      artifact.displacement = solids.deformability;
      artifact.measure = "solids";
      return artifact;
    }
    if (options.rule == "solids") throw InputError("--rule solids: does not apply: " + solids.reason);
    LogInfo("labels by PBD: %s", solids.reason.c_str());
  }

  MeshTopologyOptions topology_options;
  topology_options.weld_tolerance = options.weld_tolerance;
  topology_options.source = scene.dynamic_file.string();
  const MeshTopology topology = BuildMeshTopology(scene.dynamic_mesh, topology_options);
  std::vector<double> radii;
  std::vector<std::uint8_t> contact;
  SpheresPerWeldedVertex(topology, spheres, spheres_file, &radii, &contact);

  PbdLabelOptions label_options = options.pbd;
  // Made at the first report: only the labeling knows how many load cases
  // the budget leaves.
  std::optional<Progress> progress;
  label_options.progress = [&progress](std::int64_t done, std::int64_t total) {
    if (!progress) progress.emplace("load cases", total);
    progress->Update(done);
  };
  const PbdLabels labels = ComputePbdLabels(topology, radii, contact, label_options);
  if (progress) progress->Finish();
  const int threads = options.pbd.threads > 0 ? options.pbd.threads : omp_get_max_threads();
  LogInfo(
      "%lld load cases on %lld vertices (%d simulated components, %lld constraints, %lld glue pairs) in %.2f s "
      "with %d threads: %.3f ms per load case; %d steps, k' = %.7g, r_min %.6g and sigma %.6g (scaled mesh), "
      "rho %.6g",
      static_cast<long long>(labels.load_cases), static_cast<long long>(labels.simulated_vertices), labels.components,
      static_cast<long long>(labels.constraints), static_cast<long long>(labels.glue_constraints), labels.seconds,
      threads, 1e3 * labels.SecondsPerLoadCase(), labels.steps, labels.solver_stiffness, labels.r_min, labels.sigma,
      labels.density);

  return ToLabelsArtifact(topology, labels, options.pbd.measure);
}

void WriteLabelsExtras(const Scene& scene, const LabelsArtifact& labels, const std::string& csv,
                       const std::string& ply) {
  if (!csv.empty()) {
    WriteLabelsCsv(csv, scene.dynamic_mesh.vertices, labels.deformability);
    LogInfo("wrote %s", csv.c_str());
  }
  if (!ply.empty()) {
    WriteColoredPly(ply, scene.dynamic_mesh, labels.deformability, "deformability", ColorRamp::kRigidToDeformable, 0.0,
                    1.0, "ausbau-pbd-label: D coloured by deformability, blue rigid to red deformable");
    LogInfo("wrote %s", ply.c_str());
  }
}

}  // namespace ausbau
