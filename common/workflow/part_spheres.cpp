#include "workflow/part_spheres.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/log.h"

namespace ausbau {
namespace {

void LogTopology(const MeshTopologyStats& stats) {
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
}

void LogSpheres(const Scene& scene, const MeshTopology& topology, const MedialSpheres& spheres, int threads) {
  int contacts = 0;
  for (std::uint8_t c : spheres.contact) contacts += c;
  LogInfo(
      "%d spheres in %.3f s (%d threads, %lld nearest-point queries): radius %.6g .. %.6g%s; %d contact "
      "vertices",
      topology.VertexCount(), spheres.seconds, threads > 0 ? threads : omp_get_max_threads(),
      static_cast<long long>(spheres.nearest_queries), spheres.MinRadius(), spheres.MaxRadius(),
      scene.units.empty() ? "" : (" " + scene.units).c_str(), contacts);
  if (spheres.escaped > 0) {
    LogWarn(
        "%lld of %d vertices have no sphere: the walk inward left D's bounding box (the vertex's normal points "
        "out of its solid: a vertex shared by overlapping solids, an open or inverted surface); they are "
        "stored with radius 0 and valid 0",
        static_cast<long long>(spheres.escaped), topology.VertexCount());
  }
}

}  // namespace

void PartSpheresOptions::Check() const {
  spheres.Check();
  if (!(weld_tolerance >= 0 && weld_tolerance < 1)) {
    throw OptionError(&weld_tolerance, "weld_tolerance", "must lie in [0, 1) (a fraction of D's AABB diagonal)");
  }
}

SpheresArtifact ComputePartSpheres(const Scene& scene, const PartSpheresOptions& options) {
  options.Check();
  MeshTopologyOptions topology_options;
  topology_options.weld_tolerance = options.weld_tolerance;
  topology_options.source = scene.dynamic_file.string();  // named by "no triangle of positive area"
  const MeshTopology topology = BuildMeshTopology(scene.dynamic_mesh, topology_options);
  LogTopology(topology.stats);

  MedialSphereOptions sphere_options = options.spheres;
  Progress progress("medial spheres", topology.VertexCount());
  sphere_options.progress = [&progress](std::int64_t done, std::int64_t) { progress.Update(done); };
  const MedialSpheres spheres = ComputeMedialSpheres(topology, sphere_options);
  progress.Finish();
  LogSpheres(scene, topology, spheres, options.spheres.threads);

  SpheresArtifact artifact = ToSpheresArtifact(topology, spheres);
  artifact.units = scene.units;
  return artifact;
}

void WriteSpheresPly(const std::filesystem::path& path, const TriangleMesh& mesh, const SpheresArtifact& spheres) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (std::size_t i = 0; i < spheres.radii.size(); ++i) {
    if (!spheres.valid[i] || spheres.contact[i]) continue;
    lo = std::min(lo, spheres.radii[i]);
    hi = std::max(hi, spheres.radii[i]);
  }
  if (!std::isfinite(lo)) lo = 0.0;
  WriteColoredPly(path, mesh, spheres.radii, "radius", ColorRamp::kLargeToSmall, lo, hi,
                  "ausbau-medial-spheres: D coloured by medial-sphere radius, yellow small to blue large");
}

void WriteSpheresExtras(const Scene& scene, const SpheresArtifact& spheres, const std::string& csv,
                        const std::string& ply) {
  if (!csv.empty()) {
    WriteSpheresCsv(csv, scene.dynamic_mesh.vertices, spheres.radii);
    LogInfo("wrote %s", csv.c_str());
  }
  if (!ply.empty()) {
    WriteSpheresPly(ply, scene.dynamic_mesh, spheres);
    LogInfo("wrote %s", ply.c_str());
  }
}

}  // namespace ausbau
