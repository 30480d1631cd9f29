// scene.yaml reading and writing (format ausbau-scene/1, see schemas/scene.md).
#include "scene/scene.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "core/suggest.h"
#include "scene/mesh_io.h"
#include "scene/scene_parts.h"
#include "scene/units.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "ausbau-scene/1";
constexpr const char* kFormatV2 = "ausbau-scene/2";
constexpr double kUnitTolerance = 1e-3;

// ---------------------------------------------------------------- reading

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void Fail(const std::string& what) const { throw InputErrorAt(file_, what); }

  static int Line(const YAML::Node& node) { return node.Mark().line + 1; }

  // A compact one-line rendering of a node for error messages.
  static std::string Show(const YAML::Node& node) {
    if (!node.IsDefined() || node.IsNull()) return "nothing";
    YAML::Emitter out;
    out.SetSeqFormat(YAML::Flow);
    out.SetMapFormat(YAML::Flow);
    out << node;
    std::string s = out.c_str();
    for (char& c : s) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
  }

  // Rejects keys of a mapping outside `allowed` and duplicate keys.
  void CheckKeys(const YAML::Node& map, const std::set<std::string>& allowed, const std::string& prefix) const {
    std::set<std::string> seen;
    for (auto it = map.begin(); it != map.end(); ++it) {
      const YAML::Node key = it->first;  // a copy: the iterator yields temporaries
      const std::string k = key.IsScalar() ? key.Scalar() : Show(key);
      if (!key.IsScalar() || allowed.count(k) == 0) {
        const std::string closest = key.IsScalar() ? ClosestName(k, {allowed.begin(), allowed.end()}) : "";
        Fail("unknown key '" + prefix + k + "' (line " + std::to_string(Line(key)) +
             (closest.empty() ? "" : "; did you mean '" + prefix + closest + "'?") + ")");
      }
      if (!seen.insert(k).second) {
        Fail("duplicate key '" + prefix + k + "' (line " + std::to_string(Line(key)) + ")");
      }
    }
  }

  static bool ToNumber(const YAML::Node& node, double& value) {
    if (!node.IsScalar() || node.Tag() == "!") return false;  // quoted strings are not numbers
    return YAML::convert<double>::decode(node, value) && std::isfinite(value);
  }

  // A sequence of exactly n finite numbers.
  std::vector<double> Numbers(const YAML::Node& node, size_t n, const std::string& what) const {
    std::vector<double> out;
    bool ok = node.IsSequence() && node.size() == n;
    for (size_t i = 0; ok && i < n; ++i) {
      double v = 0;
      ok = ToNumber(node[i], v);
      out.push_back(v);
    }
    if (!ok) {
      Fail(what + " must be a list of " + std::to_string(n) + " finite numbers (got " + Show(node) + ", line " +
           std::to_string(Line(node)) + ")");
    }
    return out;
  }

  // Positions (dynamic_origin, t, bounds) share the meshes' bound: a
  // coordinate of 1e300 is finite but breaks every distance computed from it.
  Eigen::Vector3d Vector3(const YAML::Node& node, const std::string& what) const {
    const auto v = Numbers(node, 3, what);
    for (double x : v) {
      if (!(std::abs(x) <= kMaxMeshCoordinate)) {
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%.6g", x);
        Fail(what + " holds " + buf + ", absurdly far out (|value| must be <= 1e9, line " + std::to_string(Line(node)) +
             ")");
      }
    }
    return {v[0], v[1], v[2]};
  }

  Eigen::Quaterniond Quaternion(const YAML::Node& node, const std::string& what) const {
    const auto v = Numbers(node, 4, what);
    Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);  // qw, qx, qy, qz
    const double norm = q.norm();
    if (!(std::abs(norm - 1.0) <= kUnitTolerance)) {
      char buf[64];
      std::snprintf(buf, sizeof(buf), "%.6g", norm);
      Fail(what + " is not a unit quaternion (norm " + buf + ", line " + std::to_string(Line(node)) + ")");
    }
    q.normalize();
    return q;
  }

  std::string String(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar() || node.Scalar().empty()) {
      Fail(what + " must be a non-empty string (got " + Show(node) + ", line " + std::to_string(Line(node)) + ")");
    }
    // Names, units and file names reach terminals, logs, CSV headers and
    // reports: an escape sequence or a newline there is an injection, not
    // a name (the value itself is not echoed, for the same reason).
    for (const unsigned char c : node.Scalar()) {
      if (c < 0x20 || c == 0x7f) {
        Fail(what + " must not hold control characters (a newline, a tab, an escape sequence; line " +
             std::to_string(Line(node)) + ")");
      }
    }
    return node.Scalar();
  }

  Pose ReadPose(const YAML::Node& node, const std::string& what) const {
    if (!node.IsMap()) {
      Fail(what + " must be a mapping {t: [x, y, z], q: [qw, qx, qy, qz]} (got " + Show(node) + ", line " +
           std::to_string(Line(node)) + ")");
    }
    CheckKeys(node, {"t", "q"}, what + ".");
    Pose pose;
    if (node["t"]) pose.t = Vector3(node["t"], what + ".t");
    if (node["q"]) pose.q = Quaternion(node["q"], what + ".q");
    return pose;
  }

  // `goal:` is a pose {t, q} (ReadPose) or a condition {clearance, region}
  // (schemas/scene.md "Goals"); the two forms do not mix.
  void ReadGoal(const YAML::Node& node, Scene* scene) const {
    const bool condition = node.IsMap() && (node["clearance"] || node["region"]);
    if (!condition) {
      scene->goal = ReadPose(node, "goal");
      return;
    }
    if (node["t"] || node["q"]) {
      Fail("goal is either a pose {t, q} or a condition {clearance, region}, not both (line " +
           std::to_string(Line(node)) + ")");
    }
    CheckKeys(node, {"clearance", "region"}, "goal.");
    GoalCondition goal;
    if (node["clearance"]) {
      const YAML::Node c = node["clearance"];
      if (!ToNumber(c, goal.clearance) || !(goal.clearance > 0) || goal.clearance > kMaxMeshCoordinate) {
        Fail("goal.clearance must be a number > 0 and <= 1e9 (got " + Show(c) + ", line " + std::to_string(Line(c)) +
             ")");
      }
    }
    if (node["region"]) {
      const YAML::Node region = node["region"];
      if (!region.IsMap()) {
        Fail("goal.region must be a mapping {min: [x, y, z], max: [x, y, z]} (got " + Show(region) + ", line " +
             std::to_string(Line(region)) + ")");
      }
      CheckKeys(region, {"min", "max"}, "goal.region.");
      if (!region["min"]) Fail("missing required key 'goal.region.min'");
      if (!region["max"]) Fail("missing required key 'goal.region.max'");
      Aabb box;
      box.min = Vector3(region["min"], "goal.region.min");
      box.max = Vector3(region["max"], "goal.region.max");
      static const char* kAxis = "xyz";
      for (int a = 0; a < 3; ++a) {
        if (!(box.min[a] < box.max[a])) {  // a region without volume is never sampled
          char buf[160];
          std::snprintf(buf, sizeof(buf), "goal.region.min >= goal.region.max on axis %c (%.17g >= %.17g)", kAxis[a],
                        box.min[a], box.max[a]);
          Fail(buf);
        }
      }
      // The planner asks for a hair more than the region (scene_goal.cpp:
      // 1e-9 of its size and place inside each face) and converts poses
      // between conventions in doubles: a region narrower than a
      // millionth of its distance from the origin (plus 1) may hold no
      // pose it accepts, and would never be reached (issue 33).
      const double scale = 1 + box.min.cwiseAbs().cwiseMax(box.max.cwiseAbs()).maxCoeff();
      for (int a = 0; a < 3; ++a) {
        if (box.max[a] - box.min[a] < kMinGoalRegionWidth * scale) {
          char buf[320];
          std::snprintf(buf, sizeof(buf),
                        "goal.region is %.6g wide on axis %c, narrower than the planner resolves there "
                        "(%.6g = 1e-6 x (1 + its largest |coordinate|)); make it at least that wide",
                        box.max[a] - box.min[a], kAxis[a], kMinGoalRegionWidth * scale);
          Fail(buf);
        }
      }
      goal.region = box;
    }
    scene->goal_condition = goal;
  }

  Aabb ReadBounds(const YAML::Node& node) const {
    if (!node.IsMap()) {
      Fail("bounds must be a mapping {min: [x, y, z], max: [x, y, z]} (got " + Show(node) + ", line " +
           std::to_string(Line(node)) + ")");
    }
    CheckKeys(node, {"min", "max"}, "bounds.");
    if (!node["min"]) Fail("missing required key 'bounds.min'");
    if (!node["max"]) Fail("missing required key 'bounds.max'");
    Aabb box;
    box.min = Vector3(node["min"], "bounds.min");
    box.max = Vector3(node["max"], "bounds.max");
    static const char* kAxis = "xyz";
    for (int a = 0; a < 3; ++a) {
      if (box.min[a] > box.max[a]) {
        char buf[160];
        std::snprintf(buf, sizeof(buf), "bounds.min > bounds.max on axis %c (%.17g > %.17g)", kAxis[a], box.min[a],
                      box.max[a]);
        Fail(buf);
      }
    }
    return box;
  }

 private:
  std::string file_;
};

fs::path Resolve(const fs::path& dir, const std::string& p) {
  const fs::path path(p);
  return path.is_absolute() ? path : dir / path;
}

// ---------------------------------------------------------------- format /1 and /2

int ReadFormatVersion(const Reader& r, const YAML::Node& root) {
  if (!root["format"]) r.Fail(std::string("missing required key 'format' (expected ") + kFormatV2 + ")");
  const YAML::Node format = root["format"];
  if (format.IsScalar() && format.Scalar() == kFormat) return 1;
  if (format.IsScalar() && format.Scalar() == kFormatV2) return 2;
  r.Fail("unsupported format '" + (format.IsScalar() ? format.Scalar() : Reader::Show(format)) + "' (expected " +
         kFormat + " or " + kFormatV2 + ")");
}

MeshSource PlainSource(const fs::path& dir, const std::string& written) {
  MeshSource source;
  source.written = written;
  source.file = Resolve(dir, written);
  return source;
}

void SetFiles(Scene& scene) {
  scene.static_files.clear();
  for (const MeshSource& source : scene.static_sources) scene.static_files.push_back(source.file);
  scene.dynamic_file = scene.dynamic_source.file;
}

// Format /1: static is a file or a list of files, dynamic a file.
void ReadFilesV1(const Reader& r, const YAML::Node& root, const fs::path& dir, Scene& scene) {
  if (!root["static"]) r.Fail("missing required key 'static'");
  const YAML::Node stat = root["static"];
  if (stat.IsSequence()) {
    if (stat.size() == 0) {
      r.Fail("static must be a file name or a non-empty list of file names (got [], line " +
             std::to_string(Reader::Line(stat)) + ")");
    }
    for (size_t i = 0; i < stat.size(); ++i) {
      scene.static_sources.push_back(PlainSource(dir, r.String(stat[i], "static[" + std::to_string(i) + "]")));
    }
  } else {
    scene.static_sources.push_back(PlainSource(dir, r.String(stat, "static")));
  }
  if (!root["dynamic"]) r.Fail("missing required key 'dynamic'");
  scene.dynamic_source = PlainSource(dir, r.String(root["dynamic"], "dynamic"));
  SetFiles(scene);
}

// `part:` a name, an index (an unquoted whole number) or a non-empty list of them.
std::vector<PartPick> ReadPicks(const Reader& r, const YAML::Node& node, const std::string& what) {
  const auto one = [&](const YAML::Node& item) {
    if (!item.IsScalar() || item.Scalar().empty()) {
      r.Fail(what + " must be a part name, a part index or a list of them (got " + Reader::Show(item) + ", line " +
             std::to_string(Reader::Line(item)) + ")");
    }
    PartPick pick;
    const std::string text = r.String(item, what);  // (no control characters)
    const bool digits = item.Tag() != "!" && text.size() <= 9 &&
                        std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits) {
      pick.index = std::stoi(text);
    } else {
      pick.name = text;
    }
    return pick;
  };
  std::vector<PartPick> picks;
  if (node.IsSequence()) {
    if (node.size() == 0) r.Fail(what + " must not be an empty list (line " + std::to_string(Reader::Line(node)) + ")");
    for (size_t i = 0; i < node.size(); ++i) picks.push_back(one(node[i]));
  } else {
    picks.push_back(one(node));
  }
  return picks;
}

// The scene's `units:` in /2: a length unit scene/units.h converts, or
// unitless / none (numbers without a unit, as the OMPL.app scenes).
void CheckSceneUnitsV2(const Reader& r, const YAML::Node& root, const std::string& units) {
  if (units.empty() || IsSceneUnitsName(units)) return;
  r.Fail("units must be mm, cm, m, inch (or their spelled-out names), unitless or none (got '" + units + "', line " +
         std::to_string(Reader::Line(root["units"])) + ")");
}

// An entry's own `units:`: the factor that converts its mesh to the scene's units.
double ReadEntryUnits(const Reader& r, const YAML::Node& node, const std::string& what, const std::string& scene_units,
                      std::string* units) {
  *units = r.String(node, what);
  const std::optional<double> entry = MillimetresPerUnit(*units);
  if (!entry) {
    r.Fail(what + " must be mm, cm, m or inch (or their spelled-out names) (got '" + *units + "', line " +
           std::to_string(Reader::Line(node)) + ")");
  }
  const std::optional<double> world = MillimetresPerUnit(scene_units);
  if (!world) {
    r.Fail(what + ": converting from " + *units + " needs the scene's units as a length (units: mm, cm, m or inch" +
           (scene_units.empty() ? std::string(", not given") : ", got '" + scene_units + "'") + ")");
  }
  return *entry == *world ? 1.0 : *entry / *world;
}

// A mapping entry of /2: {file, part, pose, units, without}, as `allowed` says.
MeshSource ReadSourceMap(const Reader& r, const YAML::Node& node, const std::string& what, const fs::path& dir,
                         const Scene& scene, const std::set<std::string>& allowed) {
  r.CheckKeys(node, allowed, what + ".");
  MeshSource source;
  if (node["file"]) {
    source = PlainSource(dir, r.String(node["file"], what + ".file"));
  } else if (scene.assembly) {
    source.file = scene.assembly->file;  // a part of the assembly, in its units
    source.written = scene.assembly->written;
    source.units = scene.assembly->units;
    source.scale = scene.assembly->scale;
  } else {
    r.Fail(what + " needs file: (or an assembly: to pick parts from) (line " + std::to_string(Reader::Line(node)) +
           ")");
  }
  if (node["part"]) source.picks = ReadPicks(r, node["part"], what + ".part");
  if (node["without"]) source.without = ReadPicks(r, node["without"], what + ".without");
  if (node["units"]) source.scale = ReadEntryUnits(r, node["units"], what + ".units", scene.units, &source.units);
  if (node["pose"]) source.pose = r.ReadPose(node["pose"], what + ".pose");
  return source;
}

MeshSource ReadSourceV2(const Reader& r, const YAML::Node& node, const std::string& what, const fs::path& dir,
                        const Scene& scene, const std::set<std::string>& allowed) {
  if (node.IsMap()) return ReadSourceMap(r, node, what, dir, scene, allowed);
  if (!node.IsScalar()) {
    r.Fail(what + " must be a file name or a mapping {file: ..., part: ...} (got " + Reader::Show(node) + ", line " +
           std::to_string(Reader::Line(node)) + ")");
  }
  return PlainSource(dir, r.String(node, what));
}

// Format /2: assembly, static entries with parts, poses and units, dynamic with parts.
void ReadFilesV2(const Reader& r, const YAML::Node& root, const fs::path& dir, Scene& scene) {
  CheckSceneUnitsV2(r, root, scene.units);
  if (root["assembly"]) {
    const YAML::Node node = root["assembly"];
    if (node.IsMap() && !node["file"]) r.Fail("missing required key 'assembly.file'");
    scene.assembly = ReadSourceV2(r, node, "assembly", dir, scene, {"file", "units", "without"});
  }
  if (root["static"]) {
    const YAML::Node stat = root["static"];
    const std::set<std::string> keys = {"file", "part", "pose", "units"};
    if (stat.IsSequence()) {
      if (stat.size() == 0) {
        r.Fail("static must be a file name, an entry or a non-empty list of them (got [], line " +
               std::to_string(Reader::Line(stat)) + ")");
      }
      for (size_t i = 0; i < stat.size(); ++i) {
        scene.static_sources.push_back(ReadSourceV2(r, stat[i], "static[" + std::to_string(i) + "]", dir, scene, keys));
      }
    } else {
      scene.static_sources.push_back(ReadSourceV2(r, stat, "static", dir, scene, keys));
    }
  } else if (!scene.assembly) {
    r.Fail("missing required key 'static' (or 'assembly')");
  }
  if (!root["dynamic"]) r.Fail("missing required key 'dynamic'");
  scene.dynamic_source = ReadSourceV2(r, root["dynamic"], "dynamic", dir, scene, {"file", "part", "units"});
  SetFiles(scene);
}

// Records in scene.stored_spacing the spacing of single precision at the
// largest coordinate of `file` as stored (before a pose places it; a
// pose's translation is kept in double), in scene units, when it is the
// coarsest so far. The whole file counts, not only the parts picked: its
// coordinates went through float32 all the same, and the largest one is
// the conservative choice.
void NoteStoredSpacing(const MeshSource& source, const MeshFile& file, Scene& scene) {
  double magnitude = 0;
  for (const MeshPart& node : file.nodes) {
    for (const Eigen::Vector3d& v : node.mesh.vertices) magnitude = std::max(magnitude, v.cwiseAbs().maxCoeff());
  }
  if (!(magnitude > 0) || !std::isfinite(magnitude)) return;
  // float32 has a 24-bit significand: numbers in [2^e, 2^(e+1)) lie
  // 2^(e-23) apart.
  const double spacing = std::ldexp(1.0, std::ilogb(magnitude) - 23) * std::abs(source.scale);
  if (spacing > scene.stored_spacing) {
    scene.stored_spacing = spacing;
    scene.stored_magnitude = magnitude;
    scene.stored_spacing_file = source.file;
  }
}

// Loads every file once (errors name the key: "assembly: ", "static: ",
// "dynamic: "), resolves the parts, adds the assembly's rest to S, builds
// S piece by piece and D, and (in /2) checks that D is not part of S.
void LoadSceneMeshes(const Reader& r, Scene& scene) {
  MeshFileCache files;
  const auto load = [&](const MeshSource& source, const std::string& key) -> const MeshFile& {
    try {
      return files.Get(source.file);
    } catch (const InputError& e) {
      r.Fail(key + ": " + e.what());
    }
  };
  const auto resolve = [&](MeshSource& source, const std::string& key) {
    const MeshFile& file = load(source, key);
    try {
      if (source.picks.empty()) {
        source.parts.resize(file.parts.size());
        std::iota(source.parts.begin(), source.parts.end(), 0);
      } else {
        source.parts = PickParts(file, source.picks);
      }
    } catch (const InputError& e) {
      r.Fail(key + ": " + source.written + ": " + e.what());
    }
  };
  if (scene.assembly) resolve(*scene.assembly, "assembly");
  for (std::size_t i = 0; i < scene.static_sources.size(); ++i) {
    resolve(scene.static_sources[i], scene.format_version == 1 ? "static" : "static[" + std::to_string(i) + "]");
  }
  resolve(scene.dynamic_source, "dynamic");
  if (scene.assembly) {
    try {
      AddAssemblyRest(scene, files);
    } catch (const InputError& e) {
      r.Fail(e.what());
    }
  }

  for (std::size_t i = 0; i < scene.static_sources.size(); ++i) {
    AppendStaticEntry(scene, static_cast<int>(i), files.Get(scene.static_sources[i].file));
  }
  scene.dynamic_mesh = SourceMesh(scene.dynamic_source, files.Get(scene.dynamic_source.file));
  std::vector<const MeshSource*> sources = {&scene.dynamic_source};
  for (const MeshSource& source : scene.static_sources) sources.push_back(&source);
  for (const MeshSource* source : sources) NoteStoredSpacing(*source, files.Get(source->file), scene);
  // What else each importer read goes into the scene's cache keys (MeshFileHash).
  std::vector<fs::path> mesh_files = scene.static_files;
  mesh_files.push_back(scene.dynamic_file);
  for (const fs::path& file : mesh_files) {
    const std::vector<std::string>& also_read = files.Get(file).also_read;
    if (!also_read.empty()) scene.also_read[file].assign(also_read.begin(), also_read.end());
  }
  if (scene.format_version >= 2) {
    try {
      CheckDynamicApartFromStatic(scene, files);
    } catch (const InputError& e) {
      r.Fail(e.what());
    }
  }
}

// ---------------------------------------------------------------- writing

std::string Num(double v, const std::string& what, const fs::path& file) {
  if (!std::isfinite(v)) {
    throw std::runtime_error(file.string() + ": cannot write non-finite " + what);
  }
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);  // shortest round-trip form
  return std::string(buf, res.ptr);
}

std::string Vec(const double* v, int n, const std::string& what, const fs::path& file) {
  std::string s = "[";
  for (int i = 0; i < n; ++i) {
    if (i > 0) s += ", ";
    s += Num(v[i], what, file);
  }
  return s + "]";
}

std::string Vec3(const Eigen::Vector3d& v, const std::string& what, const fs::path& file) {
  return Vec(v.data(), 3, what, file);
}

// A YAML double-quoted string.
std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

std::string RelativePath(const fs::path& target, const fs::path& dir) {
  const fs::path abs_target = fs::absolute(target).lexically_normal();
  const fs::path abs_dir = fs::absolute(dir.empty() ? fs::path(".") : dir).lexically_normal();
  const fs::path rel = abs_target.lexically_relative(abs_dir);
  return (rel.empty() ? abs_target : rel).generic_string();
}

std::string PoseYaml(const Pose& pose, const std::string& what, const fs::path& file) {
  const double q[4] = {pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()};
  return "{t: " + Vec3(pose.t, what + ".t", file) + ", q: " + Vec(q, 4, what + ".q", file) + "}";
}

// What SaveSceneYaml writes: the scene's sources where they still describe
// static_files / dynamic_file, plain files where code replaced a file.
struct SourcesToWrite {
  std::optional<MeshSource> assembly;
  std::vector<MeshSource> statics;  // without the assembly's rest: assembly: implies it
  MeshSource dynamic;
  bool v2 = false;
};

SourcesToWrite ChooseSourcesToWrite(const Scene& scene) {
  SourcesToWrite out;
  out.assembly = scene.assembly;
  out.v2 = scene.assembly.has_value();
  for (std::size_t i = 0; i < scene.static_files.size(); ++i) {
    MeshSource source;
    source.file = scene.static_files[i];
    if (i < scene.static_sources.size() && scene.static_sources[i].file == scene.static_files[i]) {
      source = scene.static_sources[i];
    }
    if (source.rest_of_assembly && out.assembly) continue;
    source.rest_of_assembly = false;
    out.v2 = out.v2 || !source.Plain();
    out.statics.push_back(source);
  }
  out.dynamic.file = scene.dynamic_file;
  if (scene.dynamic_source.file == scene.dynamic_file) out.dynamic = scene.dynamic_source;
  out.v2 = out.v2 || !out.dynamic.Plain();
  return out;
}

std::string PicksYaml(const std::vector<PartPick>& picks) {
  std::string text;
  for (std::size_t i = 0; i < picks.size(); ++i) {
    text += (i > 0 ? ", " : "") + (picks[i].index >= 0 ? std::to_string(picks[i].index) : Quote(picks[i].name));
  }
  return picks.size() == 1 ? text : "[" + text + "]";
}

// One source of /2: a quoted file, or a flow mapping. A part of the
// assembly leaves out the file (and units it inherits from it).
std::string SourceYaml(const MeshSource& source, const std::optional<MeshSource>& assembly, const fs::path& path,
                       const std::string& what) {
  const fs::path dir = path.parent_path();
  const std::string file = Quote(RelativePath(source.file, dir));
  if (source.Plain()) return file;
  const bool from_assembly = assembly && source.file == assembly->file && !source.picks.empty();
  std::vector<std::string> keys;
  if (!from_assembly) keys.push_back("file: " + file);
  if (!source.picks.empty()) keys.push_back("part: " + PicksYaml(source.picks));
  if (!source.without.empty()) keys.push_back("without: " + PicksYaml(source.without));
  if (source.pose) keys.push_back("pose: " + PoseYaml(*source.pose, what + ".pose", path));
  if (!source.units.empty() && !(from_assembly && source.units == assembly->units)) {
    keys.push_back("units: " + Quote(source.units));
  }
  if (keys.empty()) return file;  // the whole assembly file: say it as a file
  std::string text = "{";
  for (std::size_t i = 0; i < keys.size(); ++i) text += (i > 0 ? ", " : "") + keys[i];
  return text + "}";
}

std::string SourcesYamlV2(const SourcesToWrite& sources, const fs::path& path) {
  std::string y;
  if (sources.assembly) y += "assembly: " + SourceYaml(*sources.assembly, std::nullopt, path, "assembly") + "\n";
  if (!sources.statics.empty()) {
    y += "static:\n";
    for (std::size_t i = 0; i < sources.statics.size(); ++i) {
      y += "  - " + SourceYaml(sources.statics[i], sources.assembly, path, "static[" + std::to_string(i) + "]") + "\n";
    }
  }
  y += "dynamic: " + SourceYaml(sources.dynamic, sources.assembly, path, "dynamic") + "\n";
  return y;
}

std::string GoalConditionYaml(const GoalCondition& goal, const fs::path& file) {
  std::string y;
  if (goal.clearance > 0) y += "clearance: " + Num(goal.clearance, "goal.clearance", file);
  if (goal.region) {
    y += std::string(y.empty() ? "" : ", ") + "region: {min: " + Vec3(goal.region->min, "goal.region.min", file) +
         ", max: " + Vec3(goal.region->max, "goal.region.max", file) + "}";
  }
  return "{" + y + "}";
}

// A top-level length in mm >= 0 (`fit_interference`, `tessellation_deflection`);
// none when the key is absent.
std::optional<double> ReadMillimetres(Reader& r, const YAML::Node& root, const char* key, const char* what) {
  if (!root[key]) return std::nullopt;
  const YAML::Node node = root[key];
  double mm = 0;
  if (!Reader::ToNumber(node, mm) || !(mm >= 0) || mm > kMaxMeshCoordinate) {
    r.Fail(std::string(key) + " must be " + what + " in mm >= 0 (got " + Reader::Show(node) + ", line " +
           std::to_string(Reader::Line(node)) + ")");
  }
  return mm;
}

// `up_axis`: one of x, y, z, -x, -y, -z ("+z" reads as "z").
std::string ReadUpAxis(Reader& r, const YAML::Node& node) {
  std::string axis = node.IsScalar() ? node.Scalar() : "";
  if (axis.size() == 2 && axis[0] == '+') axis = axis.substr(1);
  for (const char* allowed : {"x", "y", "z", "-x", "-y", "-z"}) {
    if (axis == allowed) return axis;
  }
  r.Fail("up_axis must be one of x, y, z, -x, -y, -z (got " + Reader::Show(node) + ", line " +
         std::to_string(Reader::Line(node)) + ")");
}

// Whether a mesh file is y-up as the scene reads it: glTF by its spec;
// COLLADA because assimp rotates a file's Z_UP or X_UP to Y-up on import
// (mesh_io.cpp keeps that correction).
bool YUpMeshFile(const fs::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gltf" || ext == ".glb" || ext == ".dae";
}

}  // namespace

Scene LoadScene(const fs::path& path) {
  const std::string name = path.string();
  Reader r(name);
  std::error_code ec;
  if (!fs::exists(path, ec)) r.Fail("file not found");
  if (fs::is_directory(path, ec)) r.Fail("cannot read (is a directory)");
  // A FIFO would block, /dev/zero never end: a regular file of sane size only.
  CheckInputFile(path, kMaxSceneFileBytes, "scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) r.Fail("cannot read file");
  std::stringstream text;
  text << in.rdbuf();

  YAML::Node loaded;
  try {
    loaded = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    r.Fail("YAML syntax error at line " + std::to_string(e.mark.line + 1) + ", column " +
           std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  const YAML::Node root = loaded;  // const: lookups never insert keys
  if (!root.IsMap()) r.Fail("expected a mapping of scene keys at the top level");

  Scene scene;
  try {
    scene.format_version = ReadFormatVersion(r, root);
    std::set<std::string> keys = {"format",
                                  "name",
                                  "units",
                                  "static",
                                  "dynamic",
                                  "dynamic_origin",
                                  "start",
                                  "goal",
                                  "bounds",
                                  "fit_interference",
                                  "tessellation_deflection",
                                  "up_axis"};
    if (scene.format_version >= 2) keys.insert("assembly");
    r.CheckKeys(root, keys, "");

    scene.file = path;
    scene.name = root["name"] ? r.String(root["name"], "name") : path.stem().string();
    if (root["units"]) {
      scene.units = r.String(root["units"], "units");
      // The unit's name reaches CSV headers (profile.csv) and tables: a
      // comma, a quote or a leading = + - @ there is a cell or a formula
      // (=HYPERLINK), not a unit. Unknown plain names stay a warning.
      const bool plain = std::all_of(scene.units.begin(), scene.units.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == ' ' || c == '_' || c == '.' || c == '^';
      });
      if (!plain) {
        r.Fail(
            "units must be a unit's name (mm, cm, m, inch, unitless, none): letters, digits, spaces and _.^ only "
            "(line " +
            std::to_string(Reader::Line(root["units"])) + ")");
      }
    }

    const fs::path dir = path.parent_path();
    if (scene.format_version == 1) {
      ReadFilesV1(r, root, dir, scene);
    } else {
      ReadFilesV2(r, root, dir, scene);
    }

    if (root["dynamic_origin"]) {
      scene.dynamic_origin = r.Vector3(root["dynamic_origin"], "dynamic_origin");
      scene.dynamic_origin_given = true;
    }
    if (root["start"]) scene.start = r.ReadPose(root["start"], "start");
    if (root["goal"]) r.ReadGoal(root["goal"], &scene);
    if (root["bounds"]) scene.bounds = r.ReadBounds(root["bounds"]);
    scene.fit_interference_mm = ReadMillimetres(r, root, "fit_interference", "a depth");
    scene.tessellation_deflection_mm = ReadMillimetres(r, root, "tessellation_deflection", "a chord error");
    if (root["up_axis"]) scene.up_axis = ReadUpAxis(r, root["up_axis"]);
  } catch (const YAML::Exception& e) {
    // Should not happen after the checks above; keep the one-line contract anyway.
    r.Fail("invalid scene at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  LoadSceneMeshes(r, scene);
  return scene;
}

void SaveSceneYaml(const Scene& scene, const fs::path& path) {
  WriteTextFileAtomically(path, SceneYamlText(scene, path));
}

std::string SceneYamlText(const Scene& scene, const fs::path& path) {
  const fs::path dir = path.parent_path();
  if (scene.static_files.empty() && !scene.assembly) {
    throw std::runtime_error(path.string() + ": cannot write a scene without static files");
  }
  if (scene.dynamic_file.empty()) {
    throw std::runtime_error(path.string() + ": cannot write a scene without a dynamic file");
  }
  const SourcesToWrite sources = ChooseSourcesToWrite(scene);
  std::string y;
  y += "# ausbau scene (schemas/scene.md). A pose maps D's mesh coordinates to the world:\n";
  y += "# x_world = R(q) (x - dynamic_origin) + t, q = [qw, qx, qy, qz].\n";
  y += std::string("format: ") + (sources.v2 ? kFormatV2 : kFormat) + "\n";
  const std::string name = scene.name.empty() ? path.stem().string() : scene.name;
  y += "name: " + Quote(name) + "\n";
  if (!scene.units.empty()) y += "units: " + Quote(scene.units) + "\n";
  if (sources.v2) {
    y += SourcesYamlV2(sources, path);
  } else {
    y += "static: [";
    for (size_t i = 0; i < scene.static_files.size(); ++i) {
      if (i > 0) y += ", ";
      y += Quote(RelativePath(scene.static_files[i], dir));
    }
    y += "]\n";
    y += "dynamic: " + Quote(RelativePath(scene.dynamic_file, dir)) + "\n";
  }
  if (scene.dynamic_origin_given) {
    y += "dynamic_origin: " + Vec3(scene.dynamic_origin, "dynamic_origin", path) + "\n";
  }
  y += "start: " + PoseYaml(scene.start, "start", path) + "\n";
  if (scene.goal) y += "goal: " + PoseYaml(*scene.goal, "goal", path) + "\n";
  if (!scene.goal && scene.goal_condition) y += "goal: " + GoalConditionYaml(*scene.goal_condition, path) + "\n";
  if (scene.bounds) {
    y += "bounds: {min: " + Vec3(scene.bounds->min, "bounds.min", path) +
         ", max: " + Vec3(scene.bounds->max, "bounds.max", path) + "}\n";
  }
  if (scene.fit_interference_mm) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "fit_interference: %.17g\n", *scene.fit_interference_mm);
    y += buf;
  }
  if (scene.tessellation_deflection_mm) {
    char buf[80];
    std::snprintf(buf, sizeof buf, "tessellation_deflection: %.17g  # mm\n", *scene.tessellation_deflection_mm);
    y += buf;
  }
  if (!scene.up_axis.empty()) y += "up_axis: " + Quote(scene.up_axis) + "\n";
  return y;
}

UpAxis SceneUpAxis(const Scene& scene) {
  if (!scene.up_axis.empty()) return {scene.up_axis, "scene key"};
  bool y_up = YUpMeshFile(scene.dynamic_file);
  for (const fs::path& file : scene.static_files) y_up = y_up && YUpMeshFile(file);
  if (scene.assembly) y_up = y_up && YUpMeshFile(scene.assembly->file);
  if (y_up) return {"y", "default for glTF/COLLADA data"};
  return {"z", "default for OBJ/STL/STEP data"};
}

std::string MeshFileHash(const Scene& scene, const fs::path& file) {
  const auto read = scene.also_read.find(file);
  if (read == scene.also_read.end() || read->second.empty()) return HashFile(file);
  Hasher hasher;
  hasher.Add(HashFile(file));
  for (const fs::path& other : read->second) {
    hasher.Add(other.lexically_relative(file.parent_path()).generic_string());
    hasher.Add(HashFile(other));
  }
  return hasher.HexDigest();
}

std::string DynamicContentHash(const Scene& scene) {
  const std::string file_hash = MeshFileHash(scene, scene.dynamic_file);
  const MeshSource& source = scene.dynamic_source;
  if (source.file != scene.dynamic_file || (source.picks.empty() && source.scale == 1.0)) return file_hash;
  char scale[40];
  std::snprintf(scale, sizeof scale, "%.17g", source.scale);
  std::string selection = file_hash + "\nparts:";
  for (int part : source.parts) selection += " " + std::to_string(part);
  selection += std::string("\nscale: ") + scale + "\n";
  return HashString(selection);
}

std::vector<SceneInput> SceneInputFiles(const Scene& scene, SceneInputs which) {
  std::vector<SceneInput> inputs;
  if (which == SceneInputs::kAll) {
    inputs.push_back({"scene", scene.file});
    const std::size_t count = scene.static_files.size();
    for (std::size_t i = 0; i < count; ++i) {
      inputs.push_back({count == 1 ? "static" : "static[" + std::to_string(i) + "]", scene.static_files[i]});
    }
  }
  inputs.push_back({"dynamic", scene.dynamic_file});
  return inputs;
}

std::string SceneInputHash(const Scene& scene, const SceneInput& input) {
  if (input.role == "scene") return HashFile(input.file);
  if (input.role == "dynamic") return DynamicContentHash(scene);
  return MeshFileHash(scene, input.file);
}

}  // namespace ausbau
