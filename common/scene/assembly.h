// One assembly file, one scene per part (ausbau-assembly): each part in
// turn is D, the rest of the assembly is S. The scenes use format
// ausbau-scene/2's shorthand (`assembly:` + `dynamic: {part: ...}`), so
// they reference the assembly file and copy no mesh.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/mesh.h"

namespace ausbau {

struct AssemblyPart {
  int index = 0;                 // in the file's part order (scene.yaml `part: index`)
  std::string name;              // may be empty
  long long triangles = 0;       // of the part
  Aabb box;                      // in the file's coordinates
  std::string folder;            // the part's folder under the output (AssemblyFolders)
  std::filesystem::path scene;   // the part's scene.yaml once written
  bool picked_by_index = false;  // its name is empty or shared with another part
};

// A part's name made safe for a folder or an OBJ object name: letters,
// digits, '.', '_', '-' kept, anything else '_'; empty for "", "." and "..".
std::string SafeFolderName(const std::string& name);

// The parts of an assembly file (LoadMeshFile's order), with their folder
// names: the part's name made safe for a path ([A-Za-z0-9._-], others '_'),
// or "part-<index>" when it is empty, "." / "..", or not unique (ignoring
// case). Throws LoadMeshFile's InputError.
std::vector<AssemblyPart> ListAssemblyParts(const std::filesystem::path& assembly);

struct AssemblyOptions {
  std::string units;                                 // the scenes' `units:` (empty: none written); IsSceneUnitsName
  std::string name;                                  // the scenes' name prefix; empty: the assembly file's stem
  std::optional<double> tessellation_deflection_mm;  // written into every scene (Scene::tessellation_deflection_mm)
  std::vector<int> only;                             // the parts (indices) to write a scene for; empty: every part
  // Where the assembly file came from (a STEP file it was tessellated
  // from): a JSON object written as assembly.json's "source", and per part
  // index one written as that part's "source" (empty: none).
  std::string source_json;
  std::vector<std::string> part_source_json;
};

// Writes <output>/<folder>/scene.yaml per part (D = the part, picked by name
// when its name is unique, else by index; S = the rest) and
// <output>/assembly.json (the parts, their folders and scenes), each
// atomically; then checks every part against the rest as LoadScene would
// (CheckDynamicApartFromStatic), in one pass over the file, so that a part
// whose geometry S also holds (a duplicate) is an InputError naming its
// scene. An assembly of one part has no rest: InputError. Returns the
// parts with their scenes.
std::vector<AssemblyPart> WriteAssemblyScenes(const std::filesystem::path& assembly,
                                              const std::filesystem::path& output, const AssemblyOptions& options);

}  // namespace ausbau
