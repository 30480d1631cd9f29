// ausbau-scene-gen: writes a generated scene (meshes + scene.yaml).
#include <cstdio>
#include <filesystem>

#include "cli/stage.h"
#include "fixtures/scene_families.h"

namespace ausbau {
namespace {

// No artifact and no scene read: the scene is written into a folder.
constexpr StageSpec kSceneGenStage{"ausbau-scene-gen",
                                   "Generates a small benchmark scene: meshes and scene.yaml.",
                                   SceneHash::kNoScene,
                                   {},
                                   {},
                                   "replace the scene an output folder already holds (its scene.yaml and meshes)"};

struct SceneGenOptions {
  std::string family = "rod-in-cage", output = "scene", tessellation = "coarse", world = "random";
  std::uint64_t seed = 1;
  std::int64_t triangles = 0;
  bool molded = false;
  VehicleOptions vehicle;
  const CLI::App* app = nullptr;  // which flags were given
  bool Given(const char* flag) const { return app->count(flag) > 0; }
};

// Which flags fit the family (checked in the order the errors were always
// reported; also by --validate).
void CheckFamilyFlags(const SceneGenOptions& options) {
  const SceneFamilyKind kind = KindOfSceneFamily(options.family);
  const bool box_options = options.Given("--tessellation") || options.Given("--world") || options.molded;
  if ((options.Given("--parts") || options.Given("--cell")) && kind != SceneFamilyKind::kVehicle) {
    throw InputError("--parts, --cell: apply only to the vehicle family");
  }
  if (kind == SceneFamilyKind::kVehicle && (options.triangles != 0 || box_options)) {
    throw InputError("--triangles, --tessellation, --world, --molded: not for vehicle");
  }
  if (kind == SceneFamilyKind::kBox) {
    if (options.triangles != 0) throw InputError("--triangles: does not apply to the panel-* families");
    static_cast<void>(ParseBoxTessellation(options.tessellation));  // throws on an unknown word
    static_cast<void>(ParseBoxWorld(options.world));
  } else if (box_options && kind != SceneFamilyKind::kVehicle) {
    throw InputError("--tessellation, --world, --molded: apply only to the panel-* families");
  } else if (kind == SceneFamilyKind::kUnknown) {
    throw InputError("--family: unknown family '" + options.family + "' (expected one of " + SceneFamilyNames() + ")");
  } else if (kind == SceneFamilyKind::kGenerated && options.triangles != 0) {
    throw InputError("--triangles: applies only to the clips-ds* families");
  }
}

void DeclareSceneGen(StageDefinition& stage, SceneGenOptions* options) {
  options->app = &stage.app();
  stage.app().option_defaults()->always_capture_default();  // --help shows every default
  stage.Option("--family", &options->family,
               "rod-in-cage | peg-in-plate | two-boxes | clips-ds1 .. clips-ds5 (InIState scenes) | "
               "panel-tilt-slide | panel-straight-pull | panel-channel | panel-zchannel | panel-keyhole (box scenes "
               "with an exact checker) | "
               "vehicle (a ~1.2M-triangle body shell with --parts fastened brackets; one scene per part)",
               CacheKey::kYes);
  stage.Seed(&options->seed, "random seed (varies dimensions)");
  stage.Option("--triangles", &options->triangles, "clips-ds*: target triangle count of D; 0 = the thesis's (table 14)",
               CacheKey::kYes);
  stage.Option("--tessellation", &options->tessellation,
               "panel-*: coarse (12 triangles per box) | fine (faces gridded, <= 2 mm edges)", CacheKey::kYes);
  stage.Option("--world", &options->world,
               "panel-*: identity (design frame) | random (random rotation, 2-4 m from the origin)", CacheKey::kYes);
  stage.Flag("--molded", &options->molded,
             "panel-*: the moulded twin: D one welded, closed solid (the exact union of its boxes), "
             "the same S, boxes.json and known path",
             CacheKey::kYes);
  stage.Option("--parts", &options->vehicle.parts, "vehicle: number of fastened parts (1 .. 200; every fifth riveted)",
               CacheKey::kYes);
  stage.Option("--cell", &options->vehicle.cell,
               "vehicle: grid cell of the shell in mm (2 .. 100; 10: ~1.2M triangles)", CacheKey::kYes);
  stage.OutputFolder("-o,--output", &options->output, "output folder");
  stage.CheckOptions([options] { CheckFamilyFlags(*options); });
}

// The family's generator (fixtures/scene_families.h); prints the scene.yaml
// written, or for the vehicle one line per part scene.
int GenerateFamily(const StageRun& run, const SceneGenOptions& options) {
  const SceneFamilyKind kind = KindOfSceneFamily(options.family);
  SceneFamilyOptions family{options.family, options.seed, options.triangles, {}, options.vehicle};
  if (kind == SceneFamilyKind::kBox) {
    family.box.tessellation = ParseBoxTessellation(options.tessellation);
    family.box.world = ParseBoxWorld(options.world);
    family.box.molded = options.molded;
  }
  // A user's scene is not replaced unasked (the meshes it names would be).
  // Any file in the folder may be one of them (a mesh of the same name as
  // one the family writes), so a folder that holds anything is refused too.
  // symlink_status: a link named scene.yaml counts as one.
  const std::filesystem::path folder(options.output);
  std::error_code ignored;
  if (!run.force && std::filesystem::exists(std::filesystem::symlink_status(folder / "scene.yaml", ignored))) {
    throw InputError("-o " + options.output +
                     ": the folder already holds a scene (scene.yaml); give --force to replace it, or another folder");
  }
  if (!run.force && std::filesystem::is_directory(folder, ignored) && !std::filesystem::is_empty(folder, ignored)) {
    throw InputError("-o " + options.output +
                     ": the folder is not empty (files of the same names as the scene's would be replaced); give "
                     "--force to write into it anyway, or an empty or new folder");
  }
  for (const std::string& line : GenerateSceneFamily(family, options.output)) std::printf("%s\n", line.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kSceneGenStage, DeclareSceneGen, GenerateFamily)
