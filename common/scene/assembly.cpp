#include "scene/assembly.h"

#include <cctype>
#include <map>
#include <set>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_writer.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "scene/units.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

std::string Lower(const std::string& text) {
  std::string out;
  for (const char c : text) out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string PartsJson(const fs::path& assembly, const std::vector<AssemblyPart>& parts, const fs::path& output,
                      const AssemblyOptions& options) {
  JsonWriter list(true);
  for (const AssemblyPart& part : parts) {
    if (part.scene.empty()) continue;  // not asked for (AssemblyOptions::only)
    JsonWriter entry;
    entry.Int("index", part.index)
        .String("name", part.name)
        .String("folder", part.folder)
        .String("scene", (fs::path(part.folder) / "scene.yaml").generic_string())
        .Int("triangles", part.triangles)
        .Add("box_min", JsonVector(part.box.min))
        .Add("box_max", JsonVector(part.box.max));
    if (part.index < static_cast<int>(options.part_source_json.size()) && !options.part_source_json[part.index].empty())
      entry.Add("source", options.part_source_json[part.index]);
    list.Append(entry.Text());
  }
  JsonWriter root;
  root.String("assembly", fs::absolute(assembly)
                              .lexically_normal()
                              .lexically_relative(fs::absolute(output).lexically_normal())
                              .generic_string())
      .Int("parts", static_cast<long long>(parts.size()));
  if (!options.source_json.empty()) root.Add("source", options.source_json);
  root.Add("scenes", list.Text());
  return root.Text() + "\n";
}

// An output never replaces an input.
void RefuseToReplace(const fs::path& input, const fs::path& output) {
  std::error_code error;
  if (fs::equivalent(input, output, error) && !error) {
    throw InputErrorAt(output.string(), "is the same file as the input assembly; choose another -o");
  }
}

}  // namespace

std::string SafeFolderName(const std::string& name) {
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    out += (std::isalnum(u) || c == '.' || c == '_' || c == '-') ? c : '_';
  }
  if (out == "." || out == "..") out.clear();
  return out;
}

std::vector<AssemblyPart> ListAssemblyParts(const fs::path& assembly) {
  const MeshFile file = LoadMeshFile(assembly);
  std::map<std::string, int> name_count, folder_count;
  for (int k = 0; k < static_cast<int>(file.parts.size()); ++k) {
    ++name_count[file.Part(k).name];
    ++folder_count[Lower(SafeFolderName(file.Part(k).name))];
  }
  std::vector<AssemblyPart> parts;
  for (int k = 0; k < static_cast<int>(file.parts.size()); ++k) {
    const MeshPart& node = file.Part(k);
    AssemblyPart part;
    part.index = k;
    part.name = node.name;
    part.triangles = static_cast<long long>(node.mesh.triangles.size());
    part.box = node.mesh.Bounds();
    part.picked_by_index = node.name.empty() || name_count[node.name] > 1;
    const std::string folder = SafeFolderName(node.name);
    part.folder = folder.empty() || folder_count[Lower(folder)] > 1 ? "part-" + std::to_string(k) : folder;
    parts.push_back(part);
  }
  // A name made safe may meet another part's "part-<k>": rare, but the
  // folders must differ.
  std::set<std::string> used;
  for (AssemblyPart& part : parts) {
    if (!used.insert(Lower(part.folder)).second) {
      part.folder = "part-" + std::to_string(part.index) + "-" + std::to_string(part.index);
      used.insert(Lower(part.folder));
    }
  }
  return parts;
}

std::vector<AssemblyPart> WriteAssemblyScenes(const fs::path& assembly, const fs::path& output,
                                              const AssemblyOptions& options) {
  if (!options.units.empty() && !IsSceneUnitsName(options.units)) {
    throw InputError("--units: must be mm, cm, m, inch (or their spelled-out names), unitless or none (got '" +
                     options.units + "')");
  }
  std::vector<AssemblyPart> parts = ListAssemblyParts(assembly);
  if (parts.size() < 2) {
    throw InputErrorAt(assembly.string(), "holds " + std::to_string(parts.size()) +
                                              " part; an assembly needs two or more (OBJ objects `o` or groups "
                                              "`g`, glTF or COLLADA nodes)");
  }
  const std::string prefix = options.name.empty() ? assembly.stem().string() : options.name;
  std::vector<bool> wanted(parts.size(), options.only.empty());
  for (const int k : options.only) {
    if (k < 0 || k >= static_cast<int>(parts.size()))
      throw std::runtime_error("WriteAssemblyScenes: part out of range");
    wanted[k] = true;
  }
  std::error_code error;
  for (AssemblyPart& part : parts) {
    if (!wanted[part.index]) continue;
    const fs::path folder = output / part.folder;
    fs::create_directories(folder, error);
    if (error) throw InputErrorAt(folder.string(), "cannot create the folder (" + error.message() + ")");
    Scene scene;
    scene.name = prefix + "-" + (part.name.empty() ? std::to_string(part.index) : part.name);
    scene.units = options.units;
    scene.tessellation_deflection_mm = options.tessellation_deflection_mm;
    MeshSource whole;
    whole.file = fs::absolute(assembly);
    scene.assembly = whole;
    scene.dynamic_file = whole.file;
    scene.dynamic_source = whole;
    PartPick pick;
    if (part.picked_by_index) {
      pick.index = part.index;
    } else {
      pick.name = part.name;
    }
    scene.dynamic_source.picks = {pick};
    part.scene = folder / "scene.yaml";
    RefuseToReplace(assembly, part.scene);
    SaveSceneYaml(scene, part.scene);
  }
  RefuseToReplace(assembly, output / "assembly.json");
  WriteTextFileAtomically(output / "assembly.json", PartsJson(assembly, parts, output, options));
  // Each scene read back: a part that S holds as well (two parts with the
  // same geometry at the same place) is refused here, not in a later stage.
  std::vector<AssemblyPart> written;
  for (const AssemblyPart& part : parts) {
    if (part.scene.empty()) continue;
    LoadScene(part.scene);
    written.push_back(part);
  }
  return written;
}

}  // namespace ausbau
