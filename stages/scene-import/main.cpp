// ausbau-scene-import: an OMPL.app problem (.cfg) as an Ausbau scene.yaml.
// The reading and the conversion are in common/scene/ompl_cfg.h; see
// README.md beside this file.
#include <cstdio>
#include <filesystem>

#include "cli/stage_main.h"
#include "core/log.h"
#include "scene/ompl_cfg.h"

namespace ausbau {
namespace {

const StageInfo kSceneImportStage{
    "ausbau-scene-import", "Writes a scene.yaml for an OMPL.app problem file (.cfg), meshes referenced in place."};

struct SceneImportOptions {
  std::string cfg, output = "scene.yaml";
  bool force = false;
  const CLI::App* app = nullptr;  // for the output check against the meshes
};

void DeclareSceneImport(CLI::App& app, SceneImportOptions* options) {
  options->app = &app;
  app.add_option("--ompl-cfg", options->cfg, "OMPL.app problem file (.cfg, SE(3) rigid body) to import")->required();
  app.add_option("-o,--output", options->output,
                 "the scene.yaml to write; mesh paths in it are relative to where it lies")
      ->capture_default_str();
  app.add_flag("--force", options->force,
               "write even when the output exists (otherwise an identical one is left alone and a different one "
               "is refused)");
}

int ImportScene(const SceneImportOptions& options) {
  const OmplProblem problem = ReadOmplCfg(options.cfg);
  // The meshes are inputs too: -o must not name one of them.
  CheckOutputPaths(*options.app,
                   {{"problem.robot", problem.robot.string()}, {"problem.world", problem.world.string()}});
  const Scene scene = SceneFromOmplProblem(problem);
  // Nothing is dropped without a word: each is also a comment in the scene.
  for (const std::string& note : problem.notes) {
    LogWarn("not imported: %s (how OMPL.app plans, not the problem; ausbau-plan has its own flags, README \"Flags\")",
            note.c_str());
  }
  const std::string text = OmplSceneYaml(scene, problem, options.output);
  if (!WriteImportedScene(options.output, text, options.force)) {
    LogInfo("%s is up to date (the same import); use --force to write it again", options.output.c_str());
  } else {
    LogInfo("wrote %s (dynamic_origin = OMPL.app's robot centre)", options.output.c_str());
  }
  std::printf("%s\n", options.output.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kSceneImportStage, DeclareSceneImport, ImportScene)
