// ausbau-assembly: one assembly file (a STEP assembly, or several parts in
// one OBJ, glTF, COLLADA, ... file) in, one scene per part out: D = the
// part, S = the rest. The work is in common/scene/assembly.h and, for STEP,
// common/cad/step_scenes.h; see README.md beside this file.
#include <cstdio>

#include "cad/step_scenes.h"
#include "cli/stage.h"
#include "core/format.h"
#include "core/log.h"
#include "scene/assembly.h"

namespace ausbau {
namespace {

// No artifact and no scene: the scenes go into a folder, always written anew.
constexpr StageSpec kAssemblyStage{
    "ausbau-assembly",
    "Writes one scene per part of an assembly file (D = the part, S = the rest), or lists its parts.",
    SceneHash::kNoScene,
    {},
    {},
    "accepted for a pipeline's sake: the scenes are always written anew"};

struct AssemblyStageOptions {
  std::string assembly, output = "assembly";
  AssemblyOptions scenes;
  StepTessellation tessellation;
  std::vector<std::string> dynamic;
  bool list = false;
};

void DeclareAssembly(StageDefinition& stage, AssemblyStageOptions* options) {
  stage
      .InputFile("--assembly", &options->assembly, "",
                 "the assembly: a STEP file (.step, .stp), or one mesh file holding several parts")
      ->required();
  stage.OutputFolder("-o,--output-dir", &options->output,
                     "output folder: one folder per part with scene.yaml, and assembly.json");
  stage.Option("--units", &options->scenes.units,
               "the scenes' units: mm, cm, m, inch, unitless or none (empty: not written)", CacheKey::kYes);
  stage.Option("--name", &options->scenes.name, "the scenes' name prefix (default: the assembly file's stem)",
               CacheKey::kYes);
  stage.Flag("--list", &options->list, "print the parts (index, name, triangles, box) and write nothing",
             CacheKey::kNo);
  stage.Option("--dynamic", &options->dynamic,
               "STEP: write scenes only for these parts (name, or path in the product tree: every part below "
               "it); repeatable",
               CacheKey::kYes);
  stage.Option("--deflection", &options->tessellation.deflection_mm,
               "STEP: the tessellation's chord error in mm (recorded in every scene as tessellation_deflection)",
               CacheKey::kYes);
  stage.Option("--angular-deflection", &options->tessellation.angular_deflection_rad,
               "STEP: the tessellation's angle between neighbouring triangles' normals, radians", CacheKey::kYes);
  stage.CheckOptions([options] {
    if (!IsStepFileName(options->assembly) && !options->dynamic.empty()) {
      throw InputError("--dynamic: picks parts of a STEP assembly; a mesh file's scenes pick D by name or index");
    }
  });
}

int ListStepParts(const AssemblyStageOptions& options) {
  StepTessellation tessellation = options.tessellation;
  tessellation.progress = ShowProgress("tessellating products");
  const StepAssembly assembly = ReadStepAssembly(options.assembly, tessellation);
  const std::vector<std::string> names = StepPartNames(assembly, StepMeshFileName(options.assembly));
  std::printf("index\tname\ttriangles\tbox_min\tbox_max\tpath\n");
  int index = 0;  // in the tessellated OBJ (scene.yaml `part: index`)
  for (std::size_t k = 0; k < assembly.parts.size(); ++k) {
    const StepPart& part = assembly.parts[k];
    const Aabb box = part.mesh.Bounds();
    std::string path;
    for (const std::string& node : part.path) path += (path.empty() ? "" : "/") + node;
    if (part.mesh.triangles.empty()) {  // left out of the OBJ: no surface (a wireframe, an empty compound)
      std::printf("-\t%s\t0\t-\t-\t%s\n", TerminalSafe(names[k]).c_str(), TerminalSafe(path).c_str());
      continue;
    }
    std::printf("%d\t%s\t%zu\t%g %g %g\t%g %g %g\t%s\n", index++, TerminalSafe(names[k]).c_str(),
                part.mesh.triangles.size(), box.min.x(), box.min.y(), box.min.z(), box.max.x(), box.max.y(),
                box.max.z(), TerminalSafe(path).c_str());
  }
  return kExitOk;
}

int SplitStepAssembly(const AssemblyStageOptions& options) {
  if (options.list) return ListStepParts(options);
  StepSceneOptions step;
  step.tessellation = options.tessellation;
  step.tessellation.progress = ShowProgress("tessellating products");
  if (!options.scenes.units.empty()) step.units = options.scenes.units;
  step.name = options.scenes.name;
  step.dynamic = options.dynamic;
  LogInfo("reading and tessellating %s (chord error %g mm)", options.assembly.c_str(),
          options.tessellation.deflection_mm);
  const StepScenes scenes = WriteStepAssemblyScenes(options.assembly, options.output, step);
  for (const AssemblyPart& part : scenes.parts) std::printf("%s\n", TerminalSafe(part.scene.string()).c_str());
  LogInfo("%d instances of %d products, %lld triangles (file units: %s) -> %s; wrote %zu scenes and %s/assembly.json",
          scenes.instances, scenes.products, scenes.triangles,
          scenes.file_units.empty() ? "not given" : scenes.file_units.c_str(), scenes.mesh.string().c_str(),
          scenes.parts.size(), options.output.c_str());
  if (scenes.faces_without_triangles > 0) {
    std::string parts;
    for (std::size_t k = 0; k < scenes.without_faces.size() && k < 10; ++k)
      parts += (k ? ", " : "") + TerminalSafe(scenes.without_faces[k].first) + " (" +
               std::to_string(scenes.without_faces[k].second) + ")";
    if (scenes.without_faces.size() > 10) parts += ", ...";
    LogWarn(
        "%d CAD faces could not be tessellated and are missing from the meshes: %s; those parts are open "
        "surfaces there, and a verdict where they touch D is not the CAD's",
        scenes.faces_without_triangles, parts.c_str());
  }
  for (const StepScenes::Coarser& part : scenes.coarser) {
    LogInfo("%s: %d CAD face%s tessellated only with a coarser interior (chord error at most %.3g mm there)",
            TerminalSafe(part.name).c_str(), part.faces, part.faces == 1 ? "" : "s", part.chord_error_mm);
  }
  for (const auto& [name, area] : scenes.overlapping) {
    LogWarn(
        "%s: faces of one solid lie on each other over %.4g mm^2: a face was tessellated beyond its boundary "
        "(OpenCASCADE's reading of the CAD face, not the part); its mesh is wrong there, and so is any verdict "
        "where it touches D",
        TerminalSafe(name).c_str(), area);
  }
  return kExitOk;
}

int ListParts(const std::string& assembly) {
  std::printf("index\tname\ttriangles\tbox_min\tbox_max\n");
  for (const AssemblyPart& part : ListAssemblyParts(assembly)) {
    std::printf("%d\t%s\t%lld\t%g %g %g\t%g %g %g\n", part.index, TerminalSafe(part.name).c_str(), part.triangles,
                part.box.min.x(), part.box.min.y(), part.box.min.z(), part.box.max.x(), part.box.max.y(),
                part.box.max.z());
  }
  return kExitOk;
}

int SplitAssembly(const StageRun&, const AssemblyStageOptions& options) {
  if (IsStepFileName(options.assembly)) return SplitStepAssembly(options);
  if (options.list) return ListParts(options.assembly);
  const std::vector<AssemblyPart> parts = WriteAssemblyScenes(options.assembly, options.output, options.scenes);
  for (const AssemblyPart& part : parts) std::printf("%s\n", TerminalSafe(part.scene.string()).c_str());
  LogInfo("wrote %zu scenes and %s/assembly.json", parts.size(), options.output.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kAssemblyStage, DeclareAssembly, SplitAssembly)
