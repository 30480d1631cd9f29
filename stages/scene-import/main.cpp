// ausbau-scene-import: an OMPL.app problem (.cfg) as an Ausbau scene.yaml.
// The reading and the conversion are in common/scene/ompl_cfg.h; see
// README.md beside this file.
#include <cstdio>
#include <filesystem>

#include "cli/stage.h"
#include "core/log.h"
#include "scene/ompl_cfg.h"

namespace ausbau {
namespace {

// No artifact and no scene read: the scene.yaml written is the output; an
// identical one is left alone (WriteImportedScene), its own up-to-date test.
constexpr StageSpec kSceneImportStage{
    "ausbau-scene-import",
    "Writes a scene.yaml for an OMPL.app problem file (.cfg), meshes referenced in place.",
    SceneHash::kNoScene,
    {},
    {},
    "write even when the output exists (otherwise an identical one is left alone and a different one is refused)"};

struct SceneImportOptions {
  std::string cfg, output = "scene.yaml";
};

void DeclareSceneImport(StageDefinition& stage, SceneImportOptions* options) {
  // Read by the import itself (its errors name the file and line): not hashed.
  stage.InputFile("--ompl-cfg", &options->cfg, "", "OMPL.app problem file (.cfg, SE(3) rigid body) to import")
      ->required();
  stage.ExtraOutput("-o,--output", &options->output,
                    "the scene.yaml to write; mesh paths in it are relative to where it lies");
}

int ImportScene(const StageRun& run, const SceneImportOptions& options) {
  const OmplProblem problem = ReadOmplCfg(options.cfg);
  // The meshes are inputs too: -o must not name one of them.
  run.RefuseOutputsOver({{"problem.robot", problem.robot.string()}, {"problem.world", problem.world.string()}});
  const Scene scene = SceneFromOmplProblem(problem);
  // Nothing is dropped without a word: each is also a comment in the scene.
  for (const std::string& note : problem.notes) {
    LogWarn("not imported: %s (how OMPL.app plans, not the problem; ausbau-plan has its own flags, README \"Flags\")",
            note.c_str());
  }
  const std::string text = OmplSceneYaml(scene, problem, options.output);
  if (!WriteImportedScene(options.output, text, run.force)) {
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
