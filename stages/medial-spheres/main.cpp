// ausbau-medial-spheres: phase I of the deformability labeling (thesis 5.4.1,
// algorithm 9): one sphere per vertex of D, centred near the medial axis,
// whose radius is half the local thickness. See README.md.
#include <omp.h>

#include <filesystem>
#include <string>

#include "cli/stage_main.h"
#include "core/hash.h"
#include "core/log.h"
#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

struct SpheresStageOptions {
  std::string scene;
  std::string output = "spheres.h5";
  std::string csv;
  std::string ply;
  bool force = false;
  double weld_tolerance = MeshTopologyOptions{}.weld_tolerance;
  MedialSphereOptions spheres;
};

void WriteExtras(const SpheresStageOptions& options, const Scene& scene, const SpheresArtifact& spheres) {
  if (!options.csv.empty()) {
    WriteSpheresCsv(options.csv, scene.dynamic_mesh.vertices, spheres.radii);
    LogInfo("wrote %s", options.csv.c_str());
  }
  if (!options.ply.empty()) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (std::size_t i = 0; i < spheres.radii.size(); ++i) {
      if (!spheres.valid[i] || spheres.contact[i]) continue;
      lo = std::min(lo, spheres.radii[i]);
      hi = std::max(hi, spheres.radii[i]);
    }
    if (!std::isfinite(lo)) lo = 0.0;
    WriteColoredPly(options.ply, scene.dynamic_mesh, spheres.radii, "radius", ColorRamp::kLargeToSmall, lo, hi,
                    "ausbau-medial-spheres: D coloured by medial-sphere radius, yellow small to blue large");
    LogInfo("wrote %s", options.ply.c_str());
  }
}

int Run(const SpheresStageOptions& options, const std::string& parameters) {
  options.spheres.Check();
  if (!(options.weld_tolerance >= 0 && options.weld_tolerance < 1)) {
    throw InputError("--weld-tolerance: must lie in [0, 1) (a fraction of D's AABB diagonal)");
  }
  const Scene scene = LoadScene(options.scene);
  // Only D's mesh file matters: S and the poses do not change the spheres.
  const Provenance provenance{"ausbau-medial-spheres", AUSBAU_VERSION, parameters,
                              {{"dynamic", HashFile(scene.dynamic_file)}}};
  if (!options.force &&
      ExistingProvenanceHash(options.output, kSpheresSchema, kSpheresSchemaVersion) == provenance.Hash()) {
    LogInfo("%s is up to date (same D and options); use --force to compute again", options.output.c_str());
    SpheresArtifact cached = ReadSpheresArtifact(options.output);
    WriteExtras(options, scene, cached);
    return kExitOk;
  }

  MeshTopologyOptions topology_options;
  topology_options.weld_tolerance = options.weld_tolerance;
  const MeshTopology topology = BuildMeshTopology(scene.dynamic_mesh, topology_options);
  const MeshTopologyStats& stats = topology.stats;
  LogInfo("D: %d triangles, %d vertices -> %d welded; %d patches (%d closed, %d cavities), %d triangles flipped, "
          "%d components; dropped %d degenerate and %d repeated triangles",
          stats.input_triangles, stats.input_vertices, stats.welded_vertices, stats.patches, stats.closed_patches,
          stats.cavity_patches, stats.flipped_triangles, stats.components, stats.degenerate_triangles,
          stats.duplicate_triangles);
  if (stats.boundary_edges > 0 || stats.non_manifold_edges > 0) {
    LogInfo("D is not closed: %d boundary and %d non-manifold edges (accepted)", stats.boundary_edges,
            stats.non_manifold_edges);
  }

  MedialSphereOptions sphere_options = options.spheres;
  Progress progress("medial spheres", topology.VertexCount());
  sphere_options.progress = [&progress](std::int64_t done, std::int64_t) { progress.Update(done); };
  const MedialSpheres spheres = ComputeMedialSpheres(topology, sphere_options);
  progress.Finish();
  int contacts = 0;
  for (std::uint8_t c : spheres.contact) contacts += c;
  LogInfo("%d spheres in %.3f s (%d threads, %lld nearest-point queries): radius %.6g .. %.6g%s; %d contact "
          "vertices",
          topology.VertexCount(), spheres.seconds,
          options.spheres.threads > 0 ? options.spheres.threads : omp_get_max_threads(),
          static_cast<long long>(spheres.nearest_queries), spheres.MinRadius(), spheres.MaxRadius(),
          scene.units.empty() ? "" : (" " + scene.units).c_str(), contacts);
  if (spheres.escaped > 0) {
    LogWarn("%lld of %d vertices have no sphere: the walk inward left D's bounding box (the vertex's normal points "
            "out of its solid: a vertex shared by overlapping solids, an open or inverted surface); they are "
            "stored with radius 0 and valid 0",
            static_cast<long long>(spheres.escaped), topology.VertexCount());
  }

  SpheresArtifact artifact = ToSpheresArtifact(topology, spheres);
  artifact.units = scene.units;
  WriteSpheresArtifact(options.output, artifact, provenance);
  LogInfo("wrote %s (%zu vertices of D)", options.output.c_str(), artifact.radii.size());
  WriteExtras(options, scene, artifact);
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  SpheresStageOptions options;
  CLI::App* app_ptr = nullptr;
  return RunStage(
      {"ausbau-medial-spheres",
       "Computes one medial-axis sphere per vertex of the part D (deformability labeling, phase I)."},
      argc, argv,
      [&](CLI::App& app) {
        app_ptr = &app;
        app.add_option("--scene", options.scene, "scene.yaml (only its part D is used)")->required();
        app.add_option("-o,--output", options.output, "spheres artifact (HDF5)")->capture_default_str();
        app.add_option("--csv", options.csv, "also write x,y,z,radius per vertex of D");
        app.add_option("--ply", options.ply, "also write D as PLY coloured by sphere radius");
        app.add_option("--threads", options.spheres.threads, "0 = all cores")->capture_default_str()->check(ThreadCount());
        app.add_option("--delta", options.spheres.delta, "start offset inside, fraction of D's AABB diagonal")
            ->capture_default_str();
        app.add_option("--step", options.spheres.step, "push factor eps while growing, in (0, 1)")
            ->capture_default_str();
        app.add_option("--iterations", options.spheres.cooling_iterations,
                       "cooling iterations (eps falls linearly to step / iterations)")
            ->capture_default_str();
        app.add_option("--growth-iterations", options.spheres.growth_iterations,
                       "at most this many iterations at eps = step while the sphere grows; 0 = cool from the start")
            ->capture_default_str();
        app.add_option("--weld-tolerance", options.weld_tolerance,
                       "weld vertices closer than this fraction of D's AABB diagonal")
            ->capture_default_str();
        app.add_flag("--force", options.force, "compute even when the output is up to date");
      },
      [&] { return Run(options, OptionsYaml(*app_ptr, {"scene", "output", "csv", "ply", "force", "threads"})); });
}
