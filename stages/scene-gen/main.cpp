// ausbau-scene-gen: writes a generated scene (meshes + scene.yaml).
#include <algorithm>

#include "cli/stage_main.h"
#include "core/log.h"
#include "fixtures/box_scenes.h"
#include "fixtures/clip_scenes.h"
#include "fixtures/generators.h"
#include "fixtures/vehicle.h"

namespace ausbau {
namespace {

const StageInfo kSceneGenStage{"ausbau-scene-gen", "Generates a small benchmark scene: meshes and scene.yaml."};

struct SceneGenOptions {
  std::string family = "rod-in-cage", output = "scene", tessellation = "coarse", world = "random";
  std::uint64_t seed = 1;
  std::int64_t triangles = 0;
  VehicleOptions vehicle;
  const CLI::App* app = nullptr;  // which flags were given
  bool Given(const char* flag) const { return app->count(flag) > 0; }
};

void DeclareSceneGen(CLI::App& app, SceneGenOptions* options) {
  options->app = &app;
  app.option_defaults()->always_capture_default();  // --help shows every default
  app.add_option("--family", options->family,
                 "rod-in-cage | peg-in-plate | two-boxes | clips-ds1 .. clips-ds5 (InIState scenes) | "
                 "panel-tilt-slide | panel-straight-pull | panel-channel (box scenes with an exact checker) | "
                 "vehicle (a ~1.2M-triangle body shell with --parts fastened brackets; one scene per part)");
  app.add_option("--seed", options->seed, "random seed (varies dimensions)")->check(NonNegative());
  app.add_option("--triangles", options->triangles,
                 "clips-ds*: target triangle count of D; 0 = the thesis's (table 14)");
  app.add_option("--tessellation", options->tessellation,
                 "panel-*: coarse (12 triangles per box) | fine (faces gridded, <= 2 mm edges)");
  app.add_option("--world", options->world,
                 "panel-*: identity (design frame) | random (random rotation, 2-4 m from the origin)");
  app.add_option("--parts", options->vehicle.parts,
                 "vehicle: number of fastened parts (1 .. 200; every fifth riveted)");
  app.add_option("--cell", options->vehicle.cell,
                 "vehicle: grid cell of the shell in mm (2 .. 100; 10: ~1.2M triangles)");
  app.add_option("-o,--output", options->output, "output folder");
}

// The families' generators (common/fixtures/): the scene.yaml written, or
// for the vehicle one line per part scene.
int GenerateSceneFamily(const SceneGenOptions& options) {
  const std::string& family = options.family;
  const bool box_options = options.Given("--tessellation") || options.Given("--world");
  if ((options.Given("--parts") || options.Given("--cell")) && family != "vehicle") {
    throw InputError("--parts, --cell: apply only to the vehicle family");
  }
  std::filesystem::path yaml;
  if (family == "vehicle") {
    if (options.triangles != 0 || box_options) {
      throw InputError("--triangles, --tessellation, --world: not for vehicle");
    }
    VehicleOptions vehicle = options.vehicle;
    vehicle.seed = options.seed;
    const VehicleFiles files = GenerateVehicle(vehicle, options.output);
    LogInfo("wrote %s (%lld triangles) and %zu part scenes", files.shell_obj.string().c_str(),
            static_cast<long long>(files.shell_triangles), files.parts.size());
    for (const auto& part : files.parts) {
      std::printf("%s %s\n", part.scene_yaml.string().c_str(), part.riveted ? "riveted" : "clipped");
    }
    return kExitOk;
  } else if (IsBoxSceneFamily(family)) {
    if (options.triangles != 0) throw InputError("--triangles: does not apply to the panel-* families");
    BoxSceneOptions box;
    box.seed = options.seed;
    box.tessellation = ParseBoxTessellation(options.tessellation);
    box.world = ParseBoxWorld(options.world);
    const BoxSceneFiles files = GenerateBoxScene(family, box, options.output);
    LogInfo("wrote %s, %s and %s", files.scene_yaml.string().c_str(), files.boxes_json.string().c_str(),
            files.known_path.string().c_str());
    yaml = files.scene_yaml;
  } else if (box_options) {
    throw InputError("--tessellation, --world: apply only to the panel-* families");
  } else if (IsClipSceneFamily(family)) {
    ClipSceneOptions clip;
    clip.seed = options.seed;
    clip.triangles = options.triangles;
    const ClipSceneFiles files = GenerateClipScene(family, clip, options.output);
    LogInfo("wrote %s, %s and %s", files.scene_yaml.string().c_str(), files.ground_truth_yaml.string().c_str(),
            files.ground_truth_path.string().c_str());
    yaml = files.scene_yaml;
  } else {
    const auto known = GeneratedSceneFamilies();
    if (std::find(known.begin(), known.end(), family) == known.end()) {
      std::string all;
      for (const auto& families : {known, ClipSceneFamilies(), BoxSceneFamilies()}) {
        for (const auto& f : families) all += f + ", ";
      }
      throw InputError("--family: unknown family '" + family + "' (expected one of " + all + "vehicle)");
    }
    if (options.triangles != 0) throw InputError("--triangles: applies only to the clips-ds* families");
    yaml = GenerateScene(family, options.seed, options.output);
    LogInfo("wrote %s", yaml.string().c_str());
  }
  std::printf("%s\n", yaml.string().c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kSceneGenStage, DeclareSceneGen, GenerateSceneFamily)
