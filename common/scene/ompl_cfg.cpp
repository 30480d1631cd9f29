// OMPL.app problem files (.cfg) to Ausbau scenes; see ompl_cfg.h.
#include "scene/ompl_cfg.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/suggest.h"
#include "scene/mesh_io.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// A .cfg of a few KB; anything near this is not one.
constexpr std::uint64_t kMaxCfgBytes = std::uint64_t{1} << 20;

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r");
  return s.substr(begin, end - begin + 1);
}

// The [problem] keys of omplapp's benchmark reader (benchmark/BenchmarkOptions.cpp)
// plus `sampler`, which its benchmark passes on to the planners. Those that
// make the scene are read; the others only change how OMPL.app plans.
const std::set<std::string>& UsedKeys() {
  static const std::set<std::string> keys = {
      "robot",        "world",        "start.x",      "start.y",      "start.z",      "start.theta",
      "start.axis.x", "start.axis.y", "start.axis.z", "goal.x",       "goal.y",       "goal.z",
      "goal.theta",   "goal.axis.x",  "goal.axis.y",  "goal.axis.z",  "volume.min.x", "volume.min.y",
      "volume.min.z", "volume.max.x", "volume.max.y", "volume.max.z", "name"};
  return keys;
}
const std::set<std::string>& PlanningOnlyKeys() {
  static const std::set<std::string> keys = {"objective", "objective.threshold", "threshold", "solution_length",
                                             "sampler"};
  return keys;
}

struct CfgText {
  std::map<std::string, std::string> problem;  // [problem] key -> value
  std::map<std::string, int> line;             // [problem] key -> line number
  std::vector<std::string> dropped;            // "[benchmark] time_limit = 10" in file order
};

CfgText ParseCfg(const fs::path& cfg) {
  const std::string name = cfg.string();
  CheckInputFile(cfg, kMaxCfgBytes, "problem file");
  std::ifstream in(cfg, std::ios::binary);
  if (!in) throw InputErrorAt(name, "cannot read file");
  CfgText out;
  std::string section, raw;
  for (int number = 1; std::getline(in, raw); ++number) {
    const std::string where = "line " + std::to_string(number);
    if (raw.find('\0') != std::string::npos) throw InputErrorAt(name, where + ": not a text file");
    std::string line = raw;
    const auto hash = line.find('#');  // as boost's config-file parser: a comment anywhere
    if (hash != std::string::npos) line.resize(hash);
    line = Trim(line);
    if (line.empty()) continue;
    if (line.front() == '[') {
      if (line.back() != ']') throw InputErrorAt(name, where + ": malformed section header '" + line + "'");
      section = Trim(line.substr(1, line.size() - 2));
      if (section != "problem" && section != "benchmark" && section != "planner") {
        throw InputErrorAt(
            name, where + ": unknown section [" + section + "] (expected [problem], [benchmark] or [planner])");
      }
      continue;
    }
    const auto equals = line.find('=');
    if (equals == std::string::npos || equals == 0) {
      throw InputErrorAt(name, where + ": expected 'key = value', got '" + line + "'");
    }
    const std::string key = Trim(line.substr(0, equals));
    const std::string value = Trim(line.substr(equals + 1));
    if (section.empty()) throw InputErrorAt(name, where + ": key '" + key + "' outside any section");
    if (section != "problem") {  // [benchmark] and [planner] are how OMPL.app runs, not the problem
      out.dropped.push_back("[" + section + "] " + key + " = " + value);
      continue;
    }
    if (key == "control") {
      throw InputErrorAt(name, "problem.control: control-based problems are not supported (rigid bodies only)");
    }
    if (UsedKeys().count(key) == 0 && PlanningOnlyKeys().count(key) == 0) {
      std::vector<std::string> known(UsedKeys().begin(), UsedKeys().end());
      known.insert(known.end(), PlanningOnlyKeys().begin(), PlanningOnlyKeys().end());
      const std::string closest = ClosestName(key, known);
      throw InputErrorAt(name, "problem." + key + ": unknown key (" + where +
                                   (closest.empty() ? "" : "; did you mean problem." + closest + "?") + ")");
    }
    if (out.problem.count(key) > 0) {
      throw InputErrorAt(name, "problem." + key + ": given twice (lines " + std::to_string(out.line[key]) + " and " +
                                   std::to_string(number) + ")");
    }
    out.problem[key] = value;
    out.line[key] = number;
  }
  if (in.bad()) throw InputErrorAt(name, "cannot read file");
  return out;
}

class ProblemReader {
 public:
  ProblemReader(const fs::path& cfg, const CfgText& text) : name_(cfg.string()), text_(text) {}

  bool Has(const std::string& key) const { return text_.problem.count(key) > 0; }

  const std::string& String(const std::string& key) const {
    const auto it = text_.problem.find(key);
    if (it == text_.problem.end()) throw InputErrorAt(name_, "problem." + key + ": missing required key");
    if (it->second.empty()) throw InputErrorAt(name_, "problem." + key + ": empty value" + Line(key));
    return it->second;
  }

  double Number(const std::string& key) const {
    const std::string& text = String(key);
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value)) {
      throw InputErrorAt(name_, "problem." + key + ": '" + text + "' is not a finite number" + Line(key));
    }
    // The scene's own bound on positions (scene/mesh_io.h).
    if (std::abs(value) > kMaxMeshCoordinate) {
      throw InputErrorAt(name_,
                         "problem." + key + ": " + text + " is absurdly far out (|value| must be <= 1e9)" + Line(key));
    }
    return value;
  }

  Eigen::Vector3d Vector(const std::string& prefix) const {
    return {Number(prefix + "x"), Number(prefix + "y"), Number(prefix + "z")};
  }

  // OMPL's SO3StateSpace::StateType::setAxisAngle: the axis is normalized,
  // q = (axis sin(theta / 2), cos(theta / 2)); theta in radians.
  Pose ReadPose(const std::string& which) const {
    Pose pose;
    pose.t = Vector(which + ".");
    const double theta = Number(which + ".theta");
    const Eigen::Vector3d axis = Vector(which + ".axis.");
    const double norm = axis.norm();
    if (!(norm > 0)) {
      throw InputErrorAt(name_, "problem." + which + ".axis: the rotation axis is zero" + Line(which + ".axis.x"));
    }
    const double s = std::sin(theta / 2) / norm;
    pose.q = Eigen::Quaterniond(std::cos(theta / 2), axis.x() * s, axis.y() * s, axis.z() * s);
    pose.q.normalize();
    return pose;
  }

  std::optional<Aabb> ReadVolume() const {
    static const char* const kKeys[] = {"volume.min.x", "volume.min.y", "volume.min.z",
                                        "volume.max.x", "volume.max.y", "volume.max.z"};
    int given = 0;
    for (const char* key : kKeys) given += Has(key);
    if (given == 0) return std::nullopt;
    for (const char* key : kKeys) {
      if (!Has(key)) {
        throw InputErrorAt(name_, std::string("problem.") + key +
                                      ": missing (the volume needs all six of volume.min.x .. volume.max.z, or none)");
      }
    }
    Aabb box;
    box.min = Vector("volume.min.");
    box.max = Vector("volume.max.");
    static const char kAxis[] = "xyz";
    for (int a = 0; a < 3; ++a) {
      if (box.min[a] > box.max[a]) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "volume.min.%c > volume.max.%c (%.17g > %.17g)", kAxis[a], kAxis[a], box.min[a],
                      box.max[a]);
        throw InputErrorAt(name_, std::string("problem.volume.min.") + kAxis[a] + ": " + buf);
      }
    }
    return box;
  }

 private:
  std::string Line(const std::string& key) const {
    const auto it = text_.line.find(key);
    return it == text_.line.end() ? "" : " (line " + std::to_string(it->second) + ")";
  }

  std::string name_;
  const CfgText& text_;
};

fs::path ResolveMesh(const fs::path& cfg, const std::string& file) {
  const fs::path path(file);
  return path.is_absolute() ? path : cfg.parent_path() / path;
}

// assimp's import with OMPL.app's flags (geometry/RigidBodyGeometry.cpp).
const aiScene* ImportLikeOmplApp(Assimp::Importer& importer, const fs::path& mesh) {
  CheckInputFile(mesh, kMaxMeshFileBytes, "mesh");
  const aiScene* scene =
      importer.ReadFile(mesh.string(), aiProcess_GenNormals | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                           aiProcess_SortByPType | aiProcess_OptimizeGraph);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    std::string why = importer.GetErrorString();
    for (char& c : why) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    throw InputErrorAt(mesh.string(), "cannot read mesh (" + (why.empty() ? std::string("no scene") : why) + ")");
  }
  return scene;
}

// Visits every vertex of every mesh of every node, transformed by the node
// transforms accumulated from the root in assimp's float matrices (parent *
// child), in node order: the order and arithmetic OMPL.app's sums use.
template <class Visit>
void ForEachPlacedVertex(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, Visit&& visit) {
  aiMatrix4x4 transform = parent;
  transform *= node.mTransformation;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    if (node.mMeshes[k] >= scene.mNumMeshes || scene.mMeshes[node.mMeshes[k]] == nullptr) continue;
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[k]];
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) visit(transform * mesh.mVertices[i]);
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    if (node.mChildren[c] != nullptr) ForEachPlacedVertex(scene, *node.mChildren[c], transform, visit);
  }
}

}  // namespace

OmplProblem ReadOmplCfg(const fs::path& cfg) {
  const CfgText text = ParseCfg(cfg);
  const ProblemReader r(cfg, text);
  OmplProblem problem;
  problem.file = cfg;
  if (r.Has("name")) problem.name = text.problem.at("name");
  problem.robot = ResolveMesh(cfg, r.String("robot"));
  problem.world = ResolveMesh(cfg, r.String("world"));
  problem.start = r.ReadPose("start");
  problem.goal = r.ReadPose("goal");
  problem.volume = r.ReadVolume();
  for (const auto& [key, value] : text.problem) {
    if (PlanningOnlyKeys().count(key) > 0) problem.notes.push_back("problem." + key + " = " + value);
  }
  problem.notes.insert(problem.notes.end(), text.dropped.begin(), text.dropped.end());
  return problem;
}

Eigen::Vector3d OmplRobotCenter(const fs::path& mesh) {
  Assimp::Importer importer;
  const aiScene* scene = ImportLikeOmplApp(importer, mesh);
  aiVector3D sum(0, 0, 0);  // float, as OMPL.app's sceneCenter
  unsigned count = 0;
  ForEachPlacedVertex(*scene, *scene->mRootNode, aiMatrix4x4(), [&](const aiVector3D& v) {
    sum += v;
    ++count;
  });
  if (count == 0) throw InputErrorAt(mesh.string(), "mesh has no vertex");
  sum /= static_cast<float>(count);
  const Eigen::Vector3d center(sum.x, sum.y, sum.z);
  if (!center.allFinite()) throw InputErrorAt(mesh.string(), "the mean of the vertices is not finite");
  return center;
}

Aabb OmplBounds(const OmplProblem& problem, bool* grown) {
  Aabb box;
  if (problem.volume) {
    box = *problem.volume;
  } else {
    // OMPL.app's inferEnvironmentBounds with its defaults (factor 1, add 0): the bare vertex AABB.
    Assimp::Importer importer;
    const aiScene* scene = ImportLikeOmplApp(importer, problem.world);
    ForEachPlacedVertex(*scene, *scene->mRootNode, aiMatrix4x4(),
                        [&](const aiVector3D& v) { box.Extend(Eigen::Vector3d(v.x, v.y, v.z)); });
    if (box.Empty()) throw InputErrorAt(problem.world.string(), "mesh has no vertex");
  }
  const Aabb given = box;
  box.Extend(problem.start.t);
  box.Extend(problem.goal.t);
  if (grown != nullptr) *grown = !(box.min == given.min && box.max == given.max);
  return box;
}

Scene SceneFromOmplProblem(const OmplProblem& problem) {
  const std::string cfg = problem.file.string();
  Scene scene;
  scene.file = problem.file;
  scene.name = problem.file.stem().string();
  scene.units = "unitless";  // the .dae files carry no <unit>; OMPL.app uses the numbers as they are
  scene.static_files = {problem.world};
  scene.dynamic_file = problem.robot;
  // Both meshes must load the way every stage will load them.
  try {
    scene.static_mesh = LoadMesh(problem.world);
  } catch (const InputError& e) {
    throw InputErrorAt(cfg, "problem.world: " + std::string(e.what()));
  }
  try {
    scene.dynamic_mesh = LoadMesh(problem.robot);
    scene.dynamic_origin = OmplRobotCenter(problem.robot);
  } catch (const InputError& e) {
    throw InputErrorAt(cfg, "problem.robot: " + std::string(e.what()));
  }
  scene.dynamic_origin_given = true;
  scene.start = problem.start;
  scene.goal = problem.goal;
  try {
    scene.bounds = OmplBounds(problem, nullptr);
  } catch (const InputError& e) {
    throw InputErrorAt(cfg, "problem.world: " + std::string(e.what()));
  }
  return scene;
}

std::string OmplSceneYaml(const Scene& scene, const OmplProblem& problem, const fs::path& output) {
  bool grown = false;
  OmplBounds(problem, &grown);
  std::string head = "# Imported by ausbau-scene-import from " + problem.file.filename().string();
  if (!problem.name.empty()) head += " (OMPL.app name: " + problem.name + ")";
  head += ".\n";
  head +=
      "# dynamic_origin is OMPL.app's reference point of the robot: the float mean of its imported vertices,\n"
      "# in mesh coordinates; start/goal t place it, q = theta (radians) about the cfg's axis.\n";
  head += "# bounds: " + std::string(problem.volume ? "the cfg's volume" : "the world mesh's vertex AABB (no volume)") +
          (grown ? ", grown to hold start and goal (as OMPL.app does)" : "") + ".\n";
  for (const std::string& note : problem.notes) head += "# not part of the scene (how OMPL.app plans): " + note + "\n";
  return head + SceneYamlText(scene, output);
}

bool WriteImportedScene(const fs::path& output, const std::string& text, bool force) {
  std::error_code error;
  if (!force && fs::exists(output, error)) {
    CheckOutputTarget(output);  // a folder, link or device is refused as by every stage
    std::ifstream in(output, std::ios::binary);
    std::stringstream existing;
    existing << in.rdbuf();
    if (in && existing.str() == text) return false;
    throw InputErrorAt(output.string(), "exists and differs from this import; refusing to replace it (use --force)");
  }
  WriteTextFileAtomically(output, text);
  return true;
}

}  // namespace ausbau
