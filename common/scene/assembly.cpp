#include "scene/assembly.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <system_error>

#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/json_writer.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "scene/scene_parts.h"
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

// The parts of a loaded assembly file (ListAssemblyParts).
std::vector<AssemblyPart> PartsOf(const MeshFile& file) {
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

// CheckDynamicApartFromStatic of every written scene (D = a part at the
// identity pose, S = the rest): at least kCoincidentShare of the part's
// triangles are triangles of the others (the same three vertices within
// 1e-6 of its diagonal) is InputErrorAt(<its scene.yaml>, ...). Only
// triangles inside a part's box can coincide with its own, so the
// triangles are binned once into a grid over the assembly (by their first
// vertex) and each part looks only in the cells its box overlaps: the work
// is about the triangles near each part, not all triangles per part.
void CheckNoPartDuplicated(const MeshFile& file, const std::vector<AssemblyPart>& parts) {
  const int part_count = static_cast<int>(file.parts.size());
  Aabb all;
  long long triangle_count = 0;
  for (int k = 0; k < part_count; ++k) {
    all.Extend(file.Part(k).mesh.Bounds());
    triangle_count += static_cast<long long>(file.Part(k).mesh.triangles.size());
  }
  if (triangle_count == 0) return;
  // About four triangles per cell, at most 128 cells along an axis.
  const int n = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(triangle_count) / 4)), 1, 128);
  const Eigen::Vector3d size = (all.max - all.min).cwiseMax(Eigen::Vector3d::Constant(1e-300));
  const auto cell_of = [&](double x, int axis) {
    const double at = (x - all.min[axis]) / size[axis] * n;
    return at <= 0 ? 0 : at >= n - 1 ? n - 1 : static_cast<int>(at);  // NaN-free: the boxes are finite
  };
  const auto cell_index = [&](const Eigen::Vector3d& p) {
    return (static_cast<std::size_t>(cell_of(p.z(), 2)) * n + cell_of(p.y(), 1)) * n + cell_of(p.x(), 0);
  };
  // The triangles (part, triangle) by cell, in one array (counts, then
  // offsets, then fill).
  const std::size_t cells = static_cast<std::size_t>(n) * n * n;
  std::vector<std::size_t> first(cells + 1, 0);
  for (int k = 0; k < part_count; ++k) {
    const TriangleMesh& mesh = file.Part(k).mesh;
    for (const auto& tri : mesh.triangles) ++first[cell_index(mesh.vertices[tri[0]]) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) first[c + 1] += first[c];
  std::vector<std::pair<int, int>> binned(first.back());
  std::vector<std::size_t> fill(first.begin(), first.end() - 1);
  for (int k = 0; k < part_count; ++k) {
    const TriangleMesh& mesh = file.Part(k).mesh;
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
      binned[fill[cell_index(mesh.vertices[mesh.triangles[t][0]])]++] = {k, t};
    }
  }

  for (const AssemblyPart& part : parts) {
    if (part.scene.empty()) continue;
    ThrowIfCancelled();
    const TriangleMesh& mesh = file.Part(part.index).mesh;
    const double tolerance = 1e-6 * mesh.Bounds().Diagonal();
    Aabb box = mesh.Bounds();
    box.min -= Eigen::Vector3d::Constant(2 * tolerance);
    box.max += Eigen::Vector3d::Constant(2 * tolerance);
    // The others' triangles in the cells the box overlaps, each piece
    // (part) labelled for the message.
    TriangleMesh nearby;
    std::vector<int> piece_of_triangle;
    for (int z = cell_of(box.min.z(), 2); z <= cell_of(box.max.z(), 2); ++z) {
      for (int y = cell_of(box.min.y(), 1); y <= cell_of(box.max.y(), 1); ++y) {
        for (int x = cell_of(box.min.x(), 0); x <= cell_of(box.max.x(), 0); ++x) {
          const std::size_t c = (static_cast<std::size_t>(z) * n + y) * n + x;
          for (std::size_t i = first[c]; i < first[c + 1]; ++i) {
            const auto [k, t] = binned[i];
            if (k == part.index) continue;
            const TriangleMesh& other = file.Part(k).mesh;
            const int base = static_cast<int>(nearby.vertices.size());
            for (int corner = 0; corner < 3; ++corner) {
              nearby.vertices.push_back(other.vertices[other.triangles[t][corner]]);
            }
            nearby.triangles.push_back({base, base + 1, base + 2});
            piece_of_triangle.push_back(k);
          }
        }
      }
    }
    const Coincidence same = CoincidentTriangles(mesh, nearby, piece_of_triangle, tolerance);
    const auto total = static_cast<long long>(mesh.triangles.size());
    if (total == 0 || static_cast<double>(same.triangles) < kCoincidentShare * static_cast<double>(total)) continue;
    throw InputErrorAt(part.scene.string(), "D at its start pose coincides with S: " + std::to_string(same.triangles) +
                                                " of D's " + std::to_string(total) + " triangles are triangles of S (" +
                                                PartLabel(file, same.piece) +
                                                "); S must not hold D itself (leave D's part out of S)");
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

std::vector<AssemblyPart> ListAssemblyParts(const fs::path& assembly) { return PartsOf(LoadMeshFile(assembly)); }

std::vector<AssemblyPart> WriteAssemblyScenes(const fs::path& assembly, const fs::path& output,
                                              const AssemblyOptions& options) {
  if (!options.units.empty() && !IsSceneUnitsName(options.units)) {
    throw InputError("--units: must be mm, cm, m, inch (or their spelled-out names), unitless or none (got '" +
                     options.units + "')");
  }
  const MeshFile file = LoadMeshFile(assembly);
  std::vector<AssemblyPart> parts = PartsOf(file);
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
  // A part that S holds as well (two parts with the same geometry at the
  // same place) is refused here, not in a later stage: the check LoadScene
  // makes, for all parts in one pass (loading every scene back had read
  // the whole file once per part, quadratic in the parts).
  CheckNoPartDuplicated(file, parts);
  std::vector<AssemblyPart> written;
  for (const AssemblyPart& part : parts) {
    if (!part.scene.empty()) written.push_back(part);
  }
  return written;
}

}  // namespace ausbau
