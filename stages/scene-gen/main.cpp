// ausbau-scene-gen: writes a generated scene (meshes + scene.yaml).
#include "cli/stage_main.h"
#include "core/log.h"
#include "scene/generators.h"

int main(int argc, char** argv) {
  using namespace ausbau;
  std::string family = "rod-in-cage", output = "scene";
  std::uint64_t seed = 1;
  return RunStage(
      {"ausbau-scene-gen", "Generates a small benchmark scene: meshes and scene.yaml."}, argc, argv,
      [&](CLI::App& app) {
        app.add_option("--family", family, "rod-in-cage | peg-in-plate | two-boxes")->capture_default_str();
        app.add_option("--seed", seed, "random seed (varies dimensions)")->capture_default_str();
        app.add_option("-o,--output", output, "output folder")->capture_default_str();
      },
      [&] {
        const auto yaml = GenerateScene(family, seed, output);
        LogInfo("wrote %s", yaml.string().c_str());
        std::printf("%s\n", yaml.string().c_str());
        return kExitOk;
      });
}
