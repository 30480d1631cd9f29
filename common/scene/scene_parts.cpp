#include "scene/scene_parts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <system_error>
#include <utility>
#include <vector>

#include "core/error.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

std::string CacheKey(const fs::path& path) { return fs::absolute(path).lexically_normal().string(); }

// x -> R(q) (scale x) + t, as a static entry places its mesh. Untouched
// without units and pose, so that a plain file loads bit for bit as in /1.
void Place(TriangleMesh& mesh, const MeshSource& source) {
  if (source.scale == 1.0 && !source.pose) return;
  for (Eigen::Vector3d& v : mesh.vertices) {
    v *= source.scale;
    if (source.pose) v = source.pose->Apply(v);
  }
}

bool TakesWholeFile(const MeshSource& source) { return source.picks.empty() && !source.rest_of_assembly; }

bool SameFile(const fs::path& a, const fs::path& b) {
  std::error_code error;
  const bool same = fs::equivalent(a, b, error);
  return !error && same;
}

// A triangle as the sorted grid cells of its three vertices.
using TriangleKey = std::array<long long, 9>;

struct Grid {
  Eigen::Vector3d origin;
  double cell;
  std::array<long long, 3> Cell(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d c = (p - origin) / cell;
    return {std::llround(c.x()), std::llround(c.y()), std::llround(c.z())};
  }
  TriangleKey Key(const TriangleMesh& mesh, const std::array<int, 3>& tri) const {
    std::array<std::array<long long, 3>, 3> cells = {Cell(mesh.vertices[tri[0]]), Cell(mesh.vertices[tri[1]]),
                                                     Cell(mesh.vertices[tri[2]])};
    std::sort(cells.begin(), cells.end());
    TriangleKey key;
    for (int i = 0; i < 3; ++i) {
      for (int a = 0; a < 3; ++a) key[3 * i + a] = cells[i][a];
    }
    return key;
  }
};

std::string EntryName(const Scene& scene, std::size_t entry) {
  return scene.static_sources[entry].rest_of_assembly ? "assembly" : "static[" + std::to_string(entry) + "]";
}

}  // namespace

const MeshFile& MeshFileCache::Get(const fs::path& path) {
  const std::string key = CacheKey(path);
  auto found = files_.find(key);
  if (found == files_.end()) found = files_.emplace(key, LoadMeshFile(path)).first;
  return found->second;
}

std::string PartLabel(const MeshFile& file, int part) {
  const std::string& name = file.Part(part).name;
  return name.empty() ? "#" + std::to_string(part) : name;
}

TriangleMesh SourceMesh(const MeshSource& source, const MeshFile& file) {
  TriangleMesh mesh;
  if (TakesWholeFile(source)) {
    mesh = file.Merged();
  } else {
    for (int part : source.parts) mesh.Append(file.Part(part).mesh);
  }
  Place(mesh, source);
  return mesh;
}

void AppendStaticEntry(Scene& scene, int entry, const MeshFile& file) {
  const MeshSource& source = scene.static_sources[entry];
  const auto add_piece = [&](const std::string& label, const TriangleMesh& mesh) {
    const int piece = static_cast<int>(scene.static_part_names.size());
    scene.static_part_names.push_back(label);
    scene.static_part_entry.push_back(entry);
    scene.static_part_of_triangle.insert(scene.static_part_of_triangle.end(), mesh.triangles.size(), piece);
  };
  const auto append = [&](const TriangleMesh& node_mesh) {
    if (source.scale == 1.0 && !source.pose) {
      scene.static_mesh.Append(node_mesh);
      return;
    }
    TriangleMesh placed = node_mesh;
    Place(placed, source);
    scene.static_mesh.Append(placed);
  };
  if (TakesWholeFile(source)) {
    // Every node, those without triangles too: S's vertices as LoadMesh's.
    for (std::size_t n = 0, part = 0; n < file.nodes.size(); ++n) {
      const TriangleMesh& mesh = file.nodes[n].mesh;
      append(mesh);
      if (mesh.triangles.empty()) continue;
      add_piece(
          file.parts.size() == 1 ? source.written : source.written + ":" + PartLabel(file, static_cast<int>(part)),
          mesh);
      ++part;
    }
    return;
  }
  // The assembly's rest is named as the product tree names its parts
  // ("PLATE", not "assembly.obj:PLATE": the names an engineer knows, in the
  // verdict and the report); parts picked from other files keep their file.
  for (int part : source.parts) {
    append(file.Part(part).mesh);
    add_piece(source.rest_of_assembly ? PartLabel(file, part) : source.written + ":" + PartLabel(file, part),
              file.Part(part).mesh);
  }
}

void AddAssemblyRest(Scene& scene, MeshFileCache& files) {
  MeshSource rest = *scene.assembly;
  rest.rest_of_assembly = true;
  const MeshFile& file = files.Get(rest.file);
  std::vector<bool> left_out(file.parts.size(), false);
  const MeshSource& dynamic = scene.dynamic_source;
  const bool dynamic_from_assembly = dynamic.scale == rest.scale && SameFile(dynamic.file, rest.file);
  if (dynamic_from_assembly) {
    for (int part : dynamic.parts) left_out[part] = true;
  }
  if (!rest.without.empty()) {
    try {
      for (int part : PickParts(file, rest.without)) left_out[part] = true;
    } catch (const InputError& e) {
      throw InputError("assembly.without: " + rest.written + ": " + e.what());
    }
  }
  rest.parts.clear();
  for (std::size_t part = 0; part < left_out.size(); ++part) {
    if (!left_out[part]) rest.parts.push_back(static_cast<int>(part));
  }
  if (rest.parts.empty()) {
    if (!scene.static_sources.empty()) return;
    throw InputError("assembly: " + rest.written + ": no part is left for S (it has " +
                     std::to_string(file.parts.size()) + (file.parts.size() == 1 ? " part" : " parts") +
                     (dynamic_from_assembly ? ", D takes " + std::to_string(dynamic.parts.size()) : "") +
                     "); name S under static:");
  }
  scene.static_sources.push_back(rest);
  scene.static_files.push_back(rest.file);
}

Coincidence CoincidentTriangles(const TriangleMesh& part, const TriangleMesh& other,
                                const std::vector<int>& piece_of_triangle, double tolerance) {
  Coincidence out;
  if (part.triangles.empty() || !(tolerance > 0)) return out;
  // Only triangles of `other` inside part's box (grown by the tolerance)
  // can coincide; the grid's cell indices then stay small.
  Aabb box = part.Bounds();
  box.min -= Eigen::Vector3d::Constant(2 * tolerance);
  box.max += Eigen::Vector3d::Constant(2 * tolerance);
  const Grid grid{box.min, tolerance};
  std::vector<std::pair<TriangleKey, int>> keys;
  for (std::size_t t = 0; t < other.triangles.size(); ++t) {
    const auto& tri = other.triangles[t];
    if (!box.Contains(other.vertices[tri[0]]) || !box.Contains(other.vertices[tri[1]]) ||
        !box.Contains(other.vertices[tri[2]])) {
      continue;
    }
    keys.emplace_back(grid.Key(other, tri), t < piece_of_triangle.size() ? piece_of_triangle[t] : -1);
  }
  std::sort(keys.begin(), keys.end());
  std::vector<long long> votes;
  for (const auto& tri : part.triangles) {
    const TriangleKey key = grid.Key(part, tri);
    const auto at = std::lower_bound(keys.begin(), keys.end(), std::make_pair(key, -1));
    if (at == keys.end() || at->first != key) continue;
    ++out.triangles;
    if (at->second >= 0) {
      if (votes.size() <= static_cast<std::size_t>(at->second)) votes.resize(at->second + 1, 0);
      ++votes[at->second];
    }
  }
  if (!votes.empty()) out.piece = static_cast<int>(std::max_element(votes.begin(), votes.end()) - votes.begin());
  return out;
}

void CheckDynamicApartFromStatic(const Scene& scene, MeshFileCache& files) {
  const MeshSource& dynamic = scene.dynamic_source;
  for (std::size_t i = 0; i < scene.static_sources.size(); ++i) {
    const MeshSource& stat = scene.static_sources[i];
    // A pose of its own places a copy elsewhere (a template used twice):
    // only the geometric check below applies to it.
    if (stat.pose || stat.scale != dynamic.scale || !SameFile(stat.file, dynamic.file)) continue;
    std::vector<int> common;
    std::set_intersection(stat.parts.begin(), stat.parts.end(), dynamic.parts.begin(), dynamic.parts.end(),
                          std::back_inserter(common));
    if (common.empty()) continue;
    std::string taken = "the whole of " + dynamic.written;
    if (!TakesWholeFile(stat) || !TakesWholeFile(dynamic)) {
      const MeshFile& file = files.Get(dynamic.file);
      taken = common.size() == 1 ? "part " : "parts ";
      for (std::size_t k = 0; k < common.size() && k < 5; ++k) {
        taken += (k > 0 ? ", '" : "'") + PartLabel(file, common[k]) + "'";
      }
      taken += (common.size() > 5 ? ", ... of " : " of ") + dynamic.written;
    }
    throw InputError("dynamic and " + EntryName(scene, i) + " both take " + taken +
                     ": S would hold D itself (give S the other parts with part:, or write assembly: " +
                     dynamic.written + " and dynamic: {part: ...}, which makes S the rest)");
  }

  // D installed (at its start pose) against S, triangle by triangle.
  TriangleMesh installed = scene.dynamic_mesh;
  for (Eigen::Vector3d& v : installed.vertices) v = scene.start.Apply(v - scene.dynamic_origin);
  const double diagonal = installed.Bounds().Diagonal();
  const Coincidence same =
      CoincidentTriangles(installed, scene.static_mesh, scene.static_part_of_triangle, 1e-6 * diagonal);
  const auto total = static_cast<long long>(installed.triangles.size());
  if (total == 0 || static_cast<double>(same.triangles) < kCoincidentShare * static_cast<double>(total)) return;
  const std::string where = same.piece >= 0 ? " (" + scene.static_part_names[same.piece] + ")" : "";
  throw InputError("D at its start pose coincides with S: " + std::to_string(same.triangles) + " of D's " +
                   std::to_string(total) + " triangles are triangles of S" + where +
                   "; S must not hold D itself (leave D's part out of S)");
}

}  // namespace ausbau
