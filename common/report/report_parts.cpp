#include "report/report_parts.h"

#include <algorithm>

#include "core/error.h"
#include "core/format.h"

namespace ausbau::report_internal {

namespace {

std::vector<int> ShellOfTriangle(const std::vector<ausbau::Shell>& shells, std::size_t triangles) {
  std::vector<int> of(triangles, -1);
  for (std::size_t k = 0; k < shells.size(); ++k) {
    for (const int t : shells[k].source_triangles) {
      if (t >= 0 && static_cast<std::size_t>(t) < triangles) of[t] = static_cast<int>(k);
    }
  }
  return of;
}

}  // namespace

// A name as a file gave it: assimp's placeholders ("<STL_BINARY>",
// "<OBJRoot>", "$$$DUMMY") and "defaultobject" are no name.
std::string GivenName(const std::string& text) {
  if (text.empty() || text.front() == '<' || text.front() == '$' || text == "defaultobject") return "";
  return text;
}

// A node's name for the report: the node's own, with its first mesh's name
// after a '/' where that differs; empty where the file names neither.
std::string NodeLabel(const MeshPart& node) {
  std::string name = GivenName(node.node_name);
  for (const std::string& mesh_name : node.mesh_names) {
    const std::string given = GivenName(mesh_name);
    if (given.empty() || given == name) continue;
    return name.empty() ? given : name + "/" + given;
  }
  return name;
}

int PartNamer::AddFile(const std::filesystem::path& file, int first, std::vector<Range>* ranges) {
  const std::string file_name = file.filename().string();
  MeshFile nodes;
  try {
    nodes = LoadMeshFile(file);
  } catch (const InputError&) {
    return -1;
  }
  // The nodes' triangles appended in order are LoadMesh's mesh.
  int total = 0;
  for (const MeshPart& node : nodes.nodes) {
    const int count = static_cast<int>(node.mesh.triangles.size());
    if (count == 0) continue;
    const std::string name = NodeLabel(node);
    ranges->push_back({first + total, count, name.empty() ? file_name : file_name + " \u203a " + name});
    total += count;
  }
  return total;
}

PartNamer::PartNamer(const Scene& scene, std::shared_ptr<const PartModel> shells) : shells_(std::move(shells)) {
  const int dynamic_total = static_cast<int>(scene.dynamic_mesh.triangles.size());
  if (AddFile(scene.dynamic_file, 0, &dynamic_ranges_) != dynamic_total) {
    dynamic_ranges_ = {{0, dynamic_total, scene.dynamic_file.filename().string()}};
  }
  // S is the static files appended in order: each file's triangles follow
  // the previous file's.
  int first = 0;
  for (const auto& file : scene.static_files) {
    const int count = AddFile(file, first, &static_ranges_);
    if (count < 0) {
      first = -1;
      break;
    }
    first += count;
  }
  const int static_total = static_cast<int>(scene.static_mesh.triangles.size());
  if (first != static_total) static_ranges_ = {{0, static_total, "S"}};
  if (shells_) {
    dynamic_shell_ = ShellOfTriangle(shells_->robot_shells, scene.dynamic_mesh.triangles.size());
    static_shell_ = ShellOfTriangle(shells_->static_shells, scene.static_mesh.triangles.size());
  }
}

std::string PartNamer::Base(int triangle, bool robot) const {
  const std::vector<Range>& ranges = robot ? dynamic_ranges_ : static_ranges_;
  // The last range that starts at or before `triangle`.
  const auto it =
      std::upper_bound(ranges.begin(), ranges.end(), triangle, [](int t, const Range& r) { return t < r.first; });
  if (it == ranges.begin()) return Fmt("triangle %d", triangle);
  const Range& r = *(it - 1);
  if (triangle >= r.first + r.count) return Fmt("triangle %d", triangle);
  return r.name;
}

std::string PartNamer::Triangle(int triangle, bool robot) const {
  if (triangle < 0) return "\u2013";
  std::string name = Base(triangle, robot);
  const std::vector<int>& shell_of = robot ? dynamic_shell_ : static_shell_;
  const std::vector<ausbau::Shell>* shells =
      shells_ ? (robot ? &shells_->robot_shells : &shells_->static_shells) : nullptr;
  if (shells != nullptr && shells->size() > 1 && static_cast<std::size_t>(triangle) < shell_of.size() &&
      shell_of[triangle] >= 0) {
    name += Fmt(" (shell %d)", shell_of[triangle]);
  }
  return name;
}

std::string PartNamer::Shell(int shell, bool robot) const {
  if (!shells_) return "\u2013";
  const std::vector<ausbau::Shell>& shells = robot ? shells_->robot_shells : shells_->static_shells;
  if (shell < 0 || static_cast<std::size_t>(shell) >= shells.size() || shells[shell].source_triangles.empty())
    return "\u2013";
  return Triangle(shells[shell].source_triangles.front(), robot);
}

}  // namespace ausbau::report_internal
