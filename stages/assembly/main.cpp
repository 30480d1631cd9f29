// ausbau-assembly: one assembly file (several parts in one OBJ, glTF,
// COLLADA, ... file) in, one scene per part out: D = the part, S = the rest.
// The work is in common/scene/assembly.h; see README.md beside this file.
#include <cstdio>

#include "cli/stage_main.h"
#include "core/log.h"
#include "scene/assembly.h"

namespace ausbau {
namespace {

const StageInfo kAssemblyStage{
    "ausbau-assembly",
    "Writes one scene per part of an assembly file (D = the part, S = the rest), or lists its parts."};

struct AssemblyStageOptions {
  std::string assembly, output = "assembly";
  AssemblyOptions scenes;
  bool list = false;
};

void DeclareAssembly(CLI::App& app, AssemblyStageOptions* options) {
  app.add_option("--assembly", options->assembly, "the assembly: one mesh file holding several parts")->required();
  app.add_option("-o,--output-dir", options->output,
                 "output folder: one folder per part with scene.yaml, and assembly.json")
      ->capture_default_str();
  app.add_option("--units", options->scenes.units,
                 "the scenes' units: mm, cm, m, inch, unitless or none (empty: not written)");
  app.add_option("--name", options->scenes.name, "the scenes' name prefix (default: the assembly file's stem)");
  app.add_flag("--list", options->list, "print the parts (index, name, triangles, box) and write nothing");
}

int ListParts(const std::string& assembly) {
  std::printf("index\tname\ttriangles\tbox_min\tbox_max\n");
  for (const AssemblyPart& part : ListAssemblyParts(assembly)) {
    std::printf("%d\t%s\t%lld\t%g %g %g\t%g %g %g\n", part.index, part.name.c_str(), part.triangles, part.box.min.x(),
                part.box.min.y(), part.box.min.z(), part.box.max.x(), part.box.max.y(), part.box.max.z());
  }
  return kExitOk;
}

int SplitAssembly(const AssemblyStageOptions& options) {
  if (options.list) return ListParts(options.assembly);
  const std::vector<AssemblyPart> parts = WriteAssemblyScenes(options.assembly, options.output, options.scenes);
  for (const AssemblyPart& part : parts) std::printf("%s\n", part.scene.string().c_str());
  LogInfo("wrote %zu scenes and %s/assembly.json", parts.size(), options.output.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kAssemblyStage, DeclareAssembly, SplitAssembly)
