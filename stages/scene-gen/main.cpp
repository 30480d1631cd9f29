// ausbau-scene-gen: writes a generated scene (meshes + scene.yaml).
#include <algorithm>

#include "cli/stage_main.h"
#include "core/log.h"
#include "fixtures/box_scenes.h"
#include "fixtures/clip_scenes.h"
#include "fixtures/generators.h"
#include "fixtures/vehicle.h"

int main(int argc, char** argv) {
  using namespace ausbau;
  std::string family = "rod-in-cage", output = "scene", tessellation = "coarse", world = "random";
  std::uint64_t seed = 1;
  std::int64_t triangles = 0;
  VehicleOptions vehicle;
  CLI::App* cli = nullptr;
  return RunStage(
      {"ausbau-scene-gen", "Generates a small benchmark scene: meshes and scene.yaml."}, argc, argv,
      [&](CLI::App& app) {
        cli = &app;
        app.add_option("--family", family,
                       "rod-in-cage | peg-in-plate | two-boxes | clips-ds1 .. clips-ds5 (InIState scenes) | "
                       "panel-tilt-slide | panel-straight-pull | panel-channel (box scenes with an exact checker) | "
                       "vehicle (a ~1.2M-triangle body shell with --parts fastened brackets; one scene per part)")
            ->capture_default_str();
        app.add_option("--seed", seed, "random seed (varies dimensions)")->capture_default_str()->check(NonNegative());
        app.add_option("--triangles", triangles, "clips-ds*: target triangle count of D; 0 = the thesis's (table 14)")
            ->capture_default_str();
        app.add_option("--tessellation", tessellation,
                       "panel-*: coarse (12 triangles per box) | fine (faces gridded, <= 2 mm edges)")
            ->capture_default_str();
        app.add_option("--world", world,
                       "panel-*: identity (design frame) | random (random rotation, 2-4 m from the origin)")
            ->capture_default_str();
        app.add_option("--parts", vehicle.parts, "vehicle: number of fastened parts (1 .. 200; every fifth riveted)")
            ->capture_default_str();
        app.add_option("--cell", vehicle.cell, "vehicle: grid cell of the shell in mm (2 .. 100; 10: ~1.2M triangles)")
            ->capture_default_str();
        app.add_option("-o,--output", output, "output folder")->capture_default_str();
      },
      [&] {
        std::filesystem::path yaml;
        const bool box_options = cli->count("--tessellation") > 0 || cli->count("--world") > 0;
        if ((cli->count("--parts") > 0 || cli->count("--cell") > 0) && family != "vehicle") {
          throw InputError("--parts, --cell: apply only to the vehicle family");
        }
        if (family == "vehicle") {
          if (triangles != 0 || box_options) throw InputError("--triangles, --tessellation, --world: not for vehicle");
          vehicle.seed = seed;
          const VehicleFiles files = GenerateVehicle(vehicle, output);
          LogInfo("wrote %s (%lld triangles) and %zu part scenes", files.shell_obj.string().c_str(),
                  static_cast<long long>(files.shell_triangles), files.parts.size());
          for (const auto& part : files.parts) {
            std::printf("%s %s\n", part.scene_yaml.string().c_str(), part.riveted ? "riveted" : "clipped");
          }
          return kExitOk;
        }
        if (IsBoxSceneFamily(family)) {
          if (triangles != 0) throw InputError("--triangles: does not apply to the panel-* families");
          BoxSceneOptions options;
          options.seed = seed;
          options.tessellation = ParseBoxTessellation(tessellation);
          options.world = ParseBoxWorld(world);
          const BoxSceneFiles files = GenerateBoxScene(family, options, output);
          LogInfo("wrote %s, %s and %s", files.scene_yaml.string().c_str(), files.boxes_json.string().c_str(),
                  files.known_path.string().c_str());
          yaml = files.scene_yaml;
        } else if (box_options) {
          throw InputError("--tessellation, --world: apply only to the panel-* families");
        } else if (IsClipSceneFamily(family)) {
          ClipSceneOptions options;
          options.seed = seed;
          options.triangles = triangles;
          const ClipSceneFiles files = GenerateClipScene(family, options, output);
          LogInfo("wrote %s, %s and %s", files.scene_yaml.string().c_str(), files.ground_truth_yaml.string().c_str(),
                  files.ground_truth_path.string().c_str());
          yaml = files.scene_yaml;
        } else {
          const auto known = GeneratedSceneFamilies();
          if (std::find(known.begin(), known.end(), family) == known.end()) {
            std::string all;
            for (const auto& f : known) all += f + ", ";
            for (const auto& f : ClipSceneFamilies()) all += f + ", ";
            for (const auto& f : BoxSceneFamilies()) all += f + ", ";
            all += "vehicle";
            throw InputError("--family: unknown family '" + family + "' (expected one of " + all + ")");
          }
          if (triangles != 0) throw InputError("--triangles: applies only to the clips-ds* families");
          yaml = GenerateScene(family, seed, output);
          LogInfo("wrote %s", yaml.string().c_str());
        }
        std::printf("%s\n", yaml.string().c_str());
        return kExitOk;
      });
}
