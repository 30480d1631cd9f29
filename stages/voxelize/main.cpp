// ausbau-voxelize: S as an occupancy grid in world coordinates and D's
// voxels in D's mesh coordinates, for the intersection volumes of thesis
// 5.4 (common/inistate/). See README.md beside this file.
#include <omp.h>

#include "cli/stage_main.h"
#include "core/hash.h"
#include "core/log.h"
#include "inistate/voxel_grid.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

struct VoxelizeStageOptions {
  std::string scene;
  std::string output = "voxels.h5";
  double memory_limit_gib = 2.0;
  int threads = 0;
  bool force = false;
  VoxelizeOptions voxelize;
};

int Run(VoxelizeStageOptions options, const std::string& parameters) {
  if (!(options.memory_limit_gib > 0)) throw InputError("--memory-limit: must be > 0 GiB");
  options.voxelize.memory_limit = static_cast<std::int64_t>(options.memory_limit_gib * double(1 << 30));
  options.voxelize.progress = true;
  options.voxelize.Check();
  if (options.threads < 0) throw InputError("--threads: must be >= 0");
  if (options.threads > 0) omp_set_num_threads(options.threads);

  const Scene scene = LoadScene(options.scene);
  Provenance provenance{"ausbau-voxelize", AUSBAU_VERSION, parameters, {}};
  AddSceneInputs(scene, &provenance);
  if (!options.force &&
      ExistingProvenanceHash(options.output, kVoxelsSchema, kVoxelsSchemaVersion) == provenance.Hash()) {
    LogInfo("%s is up to date (same inputs and options); use --force to voxelize again", options.output.c_str());
    return kExitOk;
  }
  LogInfo("scene %s: S %zu triangles, D %zu triangles, %d threads", scene.name.c_str(),
          scene.static_mesh.triangles.size(), scene.dynamic_mesh.triangles.size(), omp_get_max_threads());
  const SceneVoxels voxels = VoxelizeScene(scene, options.voxelize);
  const auto& s = voxels.static_stats;
  const auto& d = voxels.dynamic_stats;
  LogInfo("S: %lld surface + %lld inside voxels in %.2f s (%lld closed / %lld open triangles, %lld regions)",
          static_cast<long long>(s.surface), static_cast<long long>(s.inside), s.time_s,
          static_cast<long long>(s.closed_triangles), static_cast<long long>(s.open_triangles),
          static_cast<long long>(s.regions));
  LogInfo("D: %lld surface + %lld inside voxels in %.2f s (%lld closed / %lld open triangles, %lld regions)%s",
          static_cast<long long>(voxels.dynamic_grid.Count(kVoxelSurface)),
          static_cast<long long>(voxels.dynamic_grid.Count(kVoxelInside)), d.time_s,
          static_cast<long long>(d.closed_triangles), static_cast<long long>(d.open_triangles),
          static_cast<long long>(d.regions), voxels.shrink > 0 ? " after shrinking" : "");
  VoxelArtifactInfo info{scene.name, scene.units};
  WriteVoxelArtifact(options.output, voxels, info, provenance);
  LogInfo("voxel size %g %s, written to %s", voxels.static_grid.geometry.spacing, scene.units.c_str(),
          options.output.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  VoxelizeStageOptions options;
  CLI::App* app_ptr = nullptr;
  return RunStage(
      {"ausbau-voxelize", "Voxelizes S (world grid) and D (in its mesh frame) for intersection volumes (IV, MLIV)."},
      argc, argv,
      [&](CLI::App& app) {
        app_ptr = &app;
        app.add_option("--scene", options.scene, "scene.yaml")->required();
        app.add_option("-o,--output", options.output, "voxels artifact (HDF5, schema ausbau-voxels)")
            ->capture_default_str();
        app.add_option("--voxel-size", options.voxelize.voxel_size,
                       "voxel edge in scene units; 0 = automatic (about --voxel-budget voxels in D's AABB)")
            ->capture_default_str();
        app.add_option("--voxel-budget", options.voxelize.voxel_budget, "automatic voxel size: voxels in D's AABB")
            ->capture_default_str();
        app.add_option("--shrink", options.voxelize.shrink,
                       "erode D's voxels by this distance, scene units (thesis 5.3 baseline); 0 = none")
            ->capture_default_str();
        app.add_option("--memory-limit", options.memory_limit_gib, "GiB; larger grids are refused")
            ->capture_default_str();
        app.add_option("--threads", options.threads, "OpenMP threads; 0 = all cores")->capture_default_str()->check(ThreadCount());
        app.add_flag("--force", options.force, "voxelize even when the output is up to date");
      },
      [&] {
        return Run(options, OptionsYaml(*app_ptr, {"scene", "output", "force", "threads"}));
      });
}
