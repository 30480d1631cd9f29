// ausbau-scene-import: an OMPL.app problem (.cfg) as an Ausbau scene.yaml.
// The reading and the conversion are in common/scene/ompl_cfg.h; see
// README.md beside this file.
#include <cstdio>
#include <filesystem>

#include "cli/stage_main.h"
#include "core/log.h"
#include "scene/ompl_cfg.h"

int main(int argc, char** argv) {
  using namespace ausbau;
  std::string cfg, output = "scene.yaml";
  bool force = false;
  CLI::App* cli = nullptr;
  return RunStage(
      {"ausbau-scene-import", "Writes a scene.yaml for an OMPL.app problem file (.cfg), meshes referenced in place."},
      argc, argv,
      [&](CLI::App& app) {
        cli = &app;
        app.add_option("--ompl-cfg", cfg, "OMPL.app problem file (.cfg, SE(3) rigid body) to import")->required();
        app.add_option("-o,--output", output, "the scene.yaml to write; mesh paths in it are relative to where it lies")
            ->capture_default_str();
        app.add_flag("--force", force,
                     "write even when the output exists (otherwise an identical one is left alone and a different one "
                     "is refused)");
      },
      [&] {
        const OmplProblem problem = ReadOmplCfg(cfg);
        // The meshes are inputs too: -o must not name one of them.
        CheckOutputPaths(*cli, {{"problem.robot", problem.robot.string()}, {"problem.world", problem.world.string()}});
        const Scene scene = SceneFromOmplProblem(problem);
        const std::string text = OmplSceneYaml(scene, problem, output);
        if (!WriteImportedScene(output, text, force)) {
          LogInfo("%s is up to date (the same import); use --force to write it again", output.c_str());
          std::printf("%s\n", output.c_str());
          return kExitOk;
        }
        LogInfo("wrote %s (dynamic_origin = OMPL.app's robot centre)", output.c_str());
        std::printf("%s\n", output.c_str());
        return kExitOk;
      });
}
