// ausbau-voxelize: S as an occupancy grid in world coordinates and D's
// voxels in D's mesh coordinates, for the intersection volumes of thesis
// 5.4 (common/inistate/). See README.md beside this file.
#include <omp.h>

#include "artifact/run_files.h"
#include "cli/stage.h"
#include "core/log.h"
#include "inistate/voxel_grid.h"
#include "scene/scene.h"
#include "scene/units.h"

namespace ausbau {
namespace {

constexpr StageSpec kVoxelizeStage{
    "ausbau-voxelize",
    "Voxelizes S (world grid) and D (in its mesh frame) for intersection volumes (IV, MLIV).",
    SceneHash::kWholeScene,
    {kRunFileVoxels, kVoxelsSchema, kVoxelsSchemaVersion},
    {"inputs and options", "compute again"}};

struct VoxelizeStageOptions {
  double memory_limit_gib = 2.0;
  int threads = 0;
  VoxelizeOptions voxelize;
};

void DeclareVoxelize(StageDefinition& stage, VoxelizeStageOptions* options) {
  stage.Option(
      "--voxel-size", &options->voxelize.voxel_size,
      "voxel edge, mm (converted by the scene's units); 0 = automatic (about --voxel-budget voxels in D's AABB)",
      CacheKey::kYes);
  stage.Option("--voxel-budget", &options->voxelize.voxel_budget, "automatic voxel size: voxels in D's AABB",
               CacheKey::kYes);
  stage.Option("--shrink", &options->voxelize.shrink,
               "erode D's voxels by this distance, mm (converted by the scene's units; thesis 5.3 baseline); 0 = none",
               CacheKey::kYes);
  stage.Option("--memory-limit", &options->memory_limit_gib, "GiB; larger grids are refused", CacheKey::kNo);
  stage.Threads(&options->threads);
}

int Voxelize(const StageRun& run, const VoxelizeStageOptions& stage_options) {
  VoxelizeStageOptions options = stage_options;
  if (!(options.memory_limit_gib > 0)) throw InputError("--memory-limit: must be > 0 GiB");
  options.voxelize.memory_limit = static_cast<std::int64_t>(options.memory_limit_gib * double(1 << 30));
  options.voxelize.progress = ShowProgress("voxelize");
  options.voxelize.Check();
  const Scene& scene = run.scene;
  LogInfo("scene %s: S %zu triangles, D %zu triangles, %d threads", scene.name.c_str(),
          scene.static_mesh.triangles.size(), scene.dynamic_mesh.triangles.size(), omp_get_max_threads());
  // The flags are in mm (README "Flags"); the grid is in scene units.
  options.voxelize.voxel_size = MillimetresInSceneUnits(options.voxelize.voxel_size, scene.units);
  options.voxelize.shrink = MillimetresInSceneUnits(options.voxelize.shrink, scene.units);
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
  WriteVoxelArtifact(run.output, voxels, VoxelArtifactInfo{scene.name, scene.units}, run.provenance);
  LogInfo("voxel size %g %s, written to %s", voxels.static_grid.geometry.spacing, scene.units.c_str(),
          run.output.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kVoxelizeStage, DeclareVoxelize, Voxelize)
