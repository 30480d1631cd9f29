// ausbau-medial-spheres: phase I of the deformability labeling (thesis 5.4.1,
// algorithm 9): one sphere per vertex of D, centred near the medial axis,
// whose radius is half the local thickness. See README.md.
#include <omp.h>

#include <filesystem>
#include <string>

#include "cli/stage.h"
#include "core/log.h"
#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

struct SpheresStageOptions {
  std::string scene;
  std::string output;
  std::string csv;
  std::string ply;
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

int ComputeSpheres(const StageRun& run, const SpheresStageOptions& options) {
  options.spheres.Check();
  if (!(options.weld_tolerance >= 0 && options.weld_tolerance < 1)) {
    throw InputError("--weld-tolerance: must lie in [0, 1) (a fraction of D's AABB diagonal)");
  }
  const Scene& scene = run.scene;
  MeshTopologyOptions topology_options;
  topology_options.weld_tolerance = options.weld_tolerance;
  topology_options.source = scene.dynamic_file.string();
  const MeshTopology topology = BuildMeshTopology(scene.dynamic_mesh, topology_options);
  const MeshTopologyStats& stats = topology.stats;
  LogInfo(
      "D: %d triangles, %d vertices -> %d welded; %d patches (%d closed, %d cavities), %d triangles flipped, "
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
  LogInfo(
      "%d spheres in %.3f s (%d threads, %lld nearest-point queries): radius %.6g .. %.6g%s; %d contact "
      "vertices",
      topology.VertexCount(), spheres.seconds,
      options.spheres.threads > 0 ? options.spheres.threads : omp_get_max_threads(),
      static_cast<long long>(spheres.nearest_queries), spheres.MinRadius(), spheres.MaxRadius(),
      scene.units.empty() ? "" : (" " + scene.units).c_str(), contacts);
  if (spheres.escaped > 0) {
    LogWarn(
        "%lld of %d vertices have no sphere: the walk inward left D's bounding box (the vertex's normal points "
        "out of its solid: a vertex shared by overlapping solids, an open or inverted surface); they are "
        "stored with radius 0 and valid 0",
        static_cast<long long>(spheres.escaped), topology.VertexCount());
  }

  SpheresArtifact artifact = ToSpheresArtifact(topology, spheres);
  artifact.units = scene.units;
  WriteSpheresArtifact(run.output, artifact, run.provenance);
  LogInfo("wrote %s (%zu vertices of D)", run.output.c_str(), artifact.radii.size());
  WriteExtras(options, scene, artifact);
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  SpheresStageOptions options;
  StageDefinition stage("ausbau-medial-spheres",
                        "Computes one medial-axis sphere per vertex of the part D (deformability labeling, phase I).");
  // Only D's mesh file matters: S and the poses do not change the spheres.
  stage.SceneInput(SceneHash::kDynamicMesh, &options.scene);
  stage.Output(&options.output, "spheres.h5", kSpheresSchema, kSpheresSchemaVersion);
  stage.Option("--csv", &options.csv, "also write x,y,z,radius per vertex of D", CacheKey::kNo);
  stage.Option("--ply", &options.ply, "also write D as PLY coloured by sphere radius", CacheKey::kNo);
  stage.Threads(&options.spheres.threads);
  stage.Option("--delta", &options.spheres.delta, "start offset inside, fraction of D's AABB diagonal", CacheKey::kYes);
  stage.Option("--push-factor", &options.spheres.step, "push factor eps while growing, in (0, 1)", CacheKey::kYes);
  stage.Option("--cooling-iterations", &options.spheres.cooling_iterations,
               "cooling iterations (eps falls linearly to push factor / iterations)", CacheKey::kYes);
  stage.Option("--growth-iterations", &options.spheres.growth_iterations,
               "at most this many iterations at eps = push factor while the sphere grows; 0 = cool from the start",
               CacheKey::kYes);
  AddRenamedFlag(stage.app(), "--step", "--push-factor");
  AddRenamedFlag(stage.app(), "--iterations", "--cooling-iterations");
  stage.Option("--weld-tolerance", &options.weld_tolerance,
               "weld vertices closer than this fraction of D's AABB diagonal", CacheKey::kYes);
  return stage.Run(
      argc, argv, [&](const StageRun& run) { return ComputeSpheres(run, options); },
      [&](const StageRun& run) {
        LogInfo("%s is up to date (same D and options); use --force to compute again", run.output.c_str());
        WriteExtras(options, run.scene, ReadSpheresArtifact(run.output));
        return kExitOk;
      });
}
