// Mesh loading through assimp and a plain OBJ writer.
//
// The import reproduces OMPL.app's: triangulate, join identical vertices,
// sort by primitive type, then walk the node tree from the root accumulating
// node transforms (parent * child) and emit every mesh of every node with its
// vertices transformed; a mesh referenced by several nodes is emitted once
// per node. The COLLADA importer's up-axis correction (Z_UP files are rotated
// to Y-up through the root node's transform) is kept, as in OMPL.app.
#include "scene/mesh_io.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <sys/stat.h>
#include <assimp/Importer.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/child_process.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "core/log.h"
#include "scene/obj_check.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d out;
  out << m.a1, m.a2, m.a3, m.a4,  //
      m.b1, m.b2, m.b3, m.b4,     //
      m.c1, m.c2, m.c3, m.c4,     //
      m.d1, m.d2, m.d3, m.d4;
  return out;
}

std::string FormatVertex(const Eigen::Vector3d& v) {
  char buf[128];
  std::snprintf(buf, sizeof(buf), "%g, %g, %g", v.x(), v.y(), v.z());
  return buf;
}

// The first vertex that is not finite (or absurdly far out), as read from
// the file.
struct BadVertex {
  long index = -1;  // in the loaded mesh
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
};

// allFinite first: Eigen's maxCoeff may skip a NaN.
bool Absurd(const Eigen::Vector3d& v) { return !v.allFinite() || v.cwiseAbs().maxCoeff() > kMaxMeshCoordinate; }

std::string BadVertexText(long index, const Eigen::Vector3d& v) {
  return "vertex " + std::to_string(index) + (v.allFinite() ? " is absurdly far out (" : " is not finite (") +
         FormatVertex(v) + (v.allFinite() ? "; |coordinate| must be <= 1e9)" : ")");
}

// Checks the raw import before any post-processing touches it: every face
// index lies in its mesh (assimp does not check: a PLY face with index -1 or
// past the end would be read out of bounds) and every vertex is finite and
// within kMaxMeshCoordinate.
void CheckRawScene(const aiScene& scene, const std::string& name) {
  long index = 0;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    if (mesh == nullptr) continue;
    if (mesh->mNumVertices > 0 && mesh->mVertices == nullptr) throw InputErrorAt(name, "mesh has no vertex data");
    for (unsigned i = 0; i < mesh->mNumVertices; ++i, ++index) {
      const aiVector3D& p = mesh->mVertices[i];
      const Eigen::Vector3d v(p.x, p.y, p.z);
      // 0-based, counting the vertices of all meshes of the file in order
      // as the importer produced them (before vertex joining).
      if (Absurd(v)) throw InputErrorAt(name, BadVertexText(index, v));
    }
    if (mesh->mNumFaces > 0 && mesh->mFaces == nullptr) throw InputErrorAt(name, "mesh has no face data");
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      // assimp's triangulation aborts the process (ai_assert) on a face
      // without indices, as a corrupt OFF or PLY face count produces.
      if (face.mNumIndices == 0 || face.mIndices == nullptr) {
        throw InputErrorAt(name, "face " + std::to_string(f) + " has no vertex indices");
      }
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        if (face.mIndices[k] >= mesh->mNumVertices) {
          // A negative index in the file arrives as a huge unsigned one.
          const long long shown = face.mIndices[k] > 0x7fffffffu ? static_cast<std::int32_t>(face.mIndices[k])
                                                                 : static_cast<long long>(face.mIndices[k]);
          throw InputErrorAt(name, "face " + std::to_string(f) +
                                       (scene.mNumMeshes > 1 ? " of mesh " + std::to_string(m) : "") +
                                       " refers to vertex " + std::to_string(shown) + ", out of range (the mesh has " +
                                       std::to_string(mesh->mNumVertices) + " vertices)");
        }
      }
    }
  }
}

// Emits every node of `node`'s subtree that holds a mesh (pre-order), each
// with the triangles of its meshes placed by the accumulated transform.
// `vertex_count` counts the vertices emitted so far in all nodes: the index
// space of the merged mesh (LoadMesh), which errors and the int limit use.
void CollectNode(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent,
                 std::vector<std::string>& ancestors, MeshFile& out, std::size_t& vertex_count, BadVertex& bad) {
  const Eigen::Matrix4d transform = parent * ToEigen(node.mTransformation);
  MeshPart part;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    const unsigned mesh_index = node.mMeshes[k];
    if (mesh_index >= scene.mNumMeshes || scene.mMeshes[mesh_index] == nullptr) continue;
    const aiMesh& mesh = *scene.mMeshes[mesh_index];
    // Triangles index vertices with int: a file whose nodes instance its
    // meshes past that is refused rather than wrapped.
    if (vertex_count + mesh.mNumVertices > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw InputError("more than 2^31 vertices once every node's meshes are placed");
    }
    part.mesh_names.emplace_back(mesh.mName.C_Str());
    const int offset = static_cast<int>(part.mesh.vertices.size());
    part.mesh.vertices.reserve(part.mesh.vertices.size() + mesh.mNumVertices);
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D& p = mesh.mVertices[i];
      const Eigen::Vector4d h(p.x, p.y, p.z, 1.0);
      const Eigen::Vector4d w = transform * h;
      if (bad.index < 0 && (Absurd(h.head<3>()) || Absurd(w.head<3>()))) {
        bad.index = static_cast<long>(vertex_count);
        bad.value = Absurd(h.head<3>()) ? Eigen::Vector3d(h.head<3>()) : Eigen::Vector3d(w.head<3>());
      }
      part.mesh.vertices.push_back(w.head<3>());
      ++vertex_count;
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines are dropped
      part.mesh.triangles.push_back({offset + static_cast<int>(face.mIndices[0]),
                                     offset + static_cast<int>(face.mIndices[1]),
                                     offset + static_cast<int>(face.mIndices[2])});
    }
  }
  const std::string node_name = node.mName.C_Str();
  if (!part.mesh_names.empty()) {
    part.node_name = node_name;
    part.name = node_name;
    for (const std::string& mesh_name : part.mesh_names) {
      if (part.name.empty()) part.name = mesh_name;
    }
    part.groups = ancestors;
    out.nodes.push_back(std::move(part));
  }
  ancestors.push_back(node_name);
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    if (node.mChildren[c] != nullptr)
      CollectNode(scene, *node.mChildren[c], transform, ancestors, out, vertex_count, bad);
  }
  ancestors.pop_back();
}

// The OBJ importer also opens every file an `mtllib` line names and parses
// it as a material library. Materials are not used here, and that parser
// is more unchecked input: fuzz_mesh found "mtllib mesh.obj", which names
// the mesh itself, crashing it (the MTL parser wrote through a wild
// pointer). So for an OBJ file assimp may open only that file, and only
// before the parse: the importer opens the file, then pushes its folder
// onto the IO system's directory stack and parses; a library is opened
// during the parse (stack not empty), whatever its name. One it cannot open
// is only a warning to it.
class OnlyThisFile : public Assimp::DefaultIOSystem {
 public:
  explicit OnlyThisFile(std::string file) : file_(std::move(file)) {}
  bool Exists(const char* path) const override {
    return StackSize() == 0 && file_ == path && DefaultIOSystem::Exists(path);
  }
  Assimp::IOStream* Open(const char* path, const char* mode) override {
    return StackSize() == 0 && file_ == path ? DefaultIOSystem::Open(path, mode) : nullptr;
  }

 private:
  std::string file_;
};

// Every other format may name files of its own (a glTF buffer's or image's
// uri, a COLLADA image): assimp opens them as it finds them. Two things are
// done here. Only regular files are opened: a FIFO among them blocked the
// importer forever, a device (/dev/zero) never ends; the first one refused is
// remembered, so that the error can name it instead of assimp's "cannot
// open". And the files that did open are recorded, each once, so that the
// scene's cache keys hash them with the file (MeshFile::also_read); assimp
// also probes names that do not exist, which do not count.
class RegularFilesRecorded : public Assimp::DefaultIOSystem {
 public:
  explicit RegularFilesRecorded(std::string file) : file_(std::move(file)) {}
  bool Exists(const char* path) const override { return IsRegular(path) && DefaultIOSystem::Exists(path); }
  Assimp::IOStream* Open(const char* path, const char* mode) override {
    if (!IsRegular(path)) {
      if (refused_.empty()) refused_ = path;
      return nullptr;
    }
    Assimp::IOStream* stream = DefaultIOSystem::Open(path, mode);
    if (stream != nullptr && path != file_ &&
        std::find(opened_.begin(), opened_.end(), std::string(path)) == opened_.end()) {
      opened_.emplace_back(path);
    }
    return stream;
  }
  const std::string& refused() const { return refused_; }
  const std::vector<std::string>& opened() const { return opened_; }

 private:
  // stat(2) does not open the file, so it does not block on a FIFO. A
  // missing file passes: assimp's own "cannot open" says that well.
  static bool IsRegular(const char* path) {
    struct stat info;
    return ::stat(path, &info) != 0 || S_ISREG(info.st_mode);
  }
  std::string file_;
  std::string refused_;
  std::vector<std::string> opened_;
};

// The structure of an OFF file, checked before assimp reads it: assimp
// 5.2's OFF importer reads out of bounds on a malformed face line (fuzz_mesh
// found "@3 0 1 2" crashing it). Header (OFF, COFF, NOFF, ...), the counts,
// then per vertex a line starting with three numbers and per face a line
// "k i_1 ... i_k" with 1 <= k and every index in [0, vertices). Blank lines
// and '#' comments are skipped; what follows on a line (colours) is allowed.
void CheckOffStructure(const fs::path& path, const std::string& name) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputErrorAt(name, "cannot read mesh (cannot open file)");
  std::vector<std::vector<std::string>> lines;  // tokens of the lines that matter
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    const std::string control = FirstControlCharacter(line);
    if (!control.empty()) {
      throw InputErrorAt(
          name, "malformed OFF file (line " + std::to_string(number) + ": a control character (" + control + "))");
    }
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream tokens(line);
    std::vector<std::string> words;
    for (std::string word; tokens >> word;) words.push_back(word);
    if (!words.empty()) lines.push_back(std::move(words));
  }
  auto fail = [&](const std::string& what) { throw InputErrorAt(name, "malformed OFF file (" + what + ")"); };
  auto integer = [](const std::string& word, long long* value) {
    char* end = nullptr;
    errno = 0;
    *value = std::strtoll(word.c_str(), &end, 10);
    return errno == 0 && end != word.c_str() && end == word.c_str() + word.size();  // no trailing text, no NUL
  };
  if (lines.empty() || lines[0][0].size() < 3 || lines[0][0].compare(lines[0][0].size() - 3, 3, "OFF") != 0) {
    fail("no OFF header");
  }
  // The counts follow the header word, on its line or on the next.
  std::vector<std::string> counts(lines[0].begin() + 1, lines[0].end());
  std::size_t next = 1;
  if (counts.empty()) {
    if (lines.size() < 2) fail("no vertex and face counts");
    counts = lines[1];
    next = 2;
  }
  long long vertices = 0, faces = 0;
  if (counts.size() < 2 || !integer(counts[0], &vertices) || !integer(counts[1], &faces) || vertices < 0 || faces < 0) {
    fail("the counts are not two non-negative integers");
  }
  if (static_cast<unsigned long long>(vertices) > lines.size() ||
      static_cast<unsigned long long>(faces) > lines.size() - static_cast<std::size_t>(vertices)) {
    fail("declares " + std::to_string(vertices) + " vertices and " + std::to_string(faces) + " faces in " +
         std::to_string(lines.size()) + " lines");
  }
  for (long long v = 0; v < vertices; ++v, ++next) {
    if (next >= lines.size()) fail("fewer vertex lines than declared");
    const std::vector<std::string>& words = lines[next];
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      if (static_cast<int>(words.size()) <= k ||
          (std::strtod(words[k].c_str(), &end), end != words[k].c_str() + words[k].size())) {
        fail("vertex " + std::to_string(v) + " is not three numbers");
      }
    }
  }
  for (long long f = 0; f < faces; ++f, ++next) {
    if (next >= lines.size()) fail("fewer face lines than declared");
    const std::vector<std::string>& words = lines[next];
    long long k = 0;
    if (!integer(words[0], &k) || k < 1 || k > static_cast<long long>(words.size()) - 1) {
      fail("face " + std::to_string(f) + " does not start with its vertex count");
    }
    for (long long i = 1; i <= k; ++i) {
      long long index = 0;
      if (!integer(words[i], &index) || index < 0 || index >= vertices) {
        fail("face " + std::to_string(f) + " refers to vertex '" + words[i] + "', out of range (the mesh has " +
             std::to_string(vertices) + " vertices)");
      }
    }
  }
}

// A PLY file's layout, from its header (ReadPlyHeader).
struct PlyProperty {
  bool list = false;
  int bytes = 0;       // a scalar's size, or a list count's
  int item_bytes = 0;  // a list item's size
  bool float_count = false;
};
struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  unsigned long long min_binary_bytes = 0;  // per instance
  std::vector<PlyProperty> properties;
};
struct PlyLayout {
  bool ascii = false;
  bool big_endian = false;
  std::size_t header_bytes = 0;
  std::vector<PlyElement> elements;
};

bool IsPlyFloat(const std::string& type) {
  return type == "float" || type == "float32" || type == "double" || type == "float64";
}

// A binary list count (1, 2, 4 or 8 bytes) as a double; an integer count
// read as unsigned (a negative signed count becomes a huge one, which the
// caller refuses, as it refuses a negative or NaN float count).
double DecodePlyCount(const unsigned char* raw, int bytes, bool is_float, bool big_endian) {
  std::uint64_t bits = 0;
  for (int k = 0; k < bytes; ++k) bits |= std::uint64_t{raw[big_endian ? bytes - 1 - k : k]} << (8 * k);
  if (is_float && bytes == 4) {
    float f;
    const std::uint32_t b32 = static_cast<std::uint32_t>(bits);
    std::memcpy(&f, &b32, 4);
    return f;
  }
  if (is_float) {
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
  }
  return static_cast<double>(bits);
}

// The header of a PLY file, checked before assimp reads it: assimp 5.2's
// PLY importer loops forever at the end of a file without an end_header line
// (fuzz_mesh found it), and loops once per declared element, reading past the
// end of the file, for a count the file cannot hold. Refused: no "ply" line
// first, no format line, an element line without a non-negative integer count,
// a property of an unknown type, no end_header within the first 1 MiB, and
// element counts whose instances cannot fit in the bytes after the header
// (binary: the sizes of the properties, a list at least its count; ASCII: a
// property at least one character and one separator).
PlyLayout ReadPlyHeader(const fs::path& path, const std::string& name) {
  constexpr std::size_t kMaxHeaderBytes = std::size_t{1} << 20;
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputErrorAt(name, "cannot read mesh (cannot open file)");
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw InputErrorAt(name, "cannot read mesh (" + ec.message() + ")");
  // Only the first 1 MiB is read (a binary body may hold no line break).
  std::string prefix(static_cast<std::size_t>(std::min<std::uintmax_t>(size, kMaxHeaderBytes)), '\0');
  file.read(prefix.data(), static_cast<std::streamsize>(prefix.size()));
  prefix.resize(static_cast<std::size_t>(file.gcount()));
  std::istringstream in(prefix);
  auto fail = [&](const std::string& what) { throw InputErrorAt(name, "malformed PLY file (" + what + ")"); };
  auto scalar_bytes = [](const std::string& type) -> int {
    static const std::pair<const char*, int> kTypes[] = {{"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},
                                                         {"short", 2}, {"ushort", 2},  {"int16", 2},  {"uint16", 2},
                                                         {"int", 4},   {"uint", 4},    {"int32", 4},  {"uint32", 4},
                                                         {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    for (const auto& [word, bytes] : kTypes) {
      if (type == word) return bytes;
    }
    return 0;
  };
  std::vector<PlyElement> elements;
  bool ascii = false, big_endian = false, format = false, ended = false;
  std::size_t header_bytes = 0;
  std::string line;
  for (int number = 0; !ended && std::getline(in, line); ++number) {
    header_bytes += line.size() + 1;
    if (header_bytes > prefix.size() && prefix.size() == kMaxHeaderBytes) {
      fail("no end_header line in the first 1 MiB");
    }
    const std::string control = FirstControlCharacter(line);
    if (!control.empty()) fail("a control character (" + control + ") in header line " + std::to_string(number + 1));
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream tokens(line);
    std::vector<std::string> words;
    for (std::string word; tokens >> word;) words.push_back(word);
    if (number == 0) {
      if (words.size() != 1 || words[0] != "ply") fail("the first line is not 'ply'");
      continue;
    }
    if (words.empty()) continue;
    if (words[0] == "end_header") {
      ended = true;
    } else if (words[0] == "format") {
      if (words.size() < 2 ||
          (words[1] != "ascii" && words[1] != "binary_little_endian" && words[1] != "binary_big_endian")) {
        fail("unknown format line '" + line + "'");
      }
      ascii = words[1] == "ascii";
      big_endian = words[1] == "binary_big_endian";
      format = true;
    } else if (words[0] == "element") {
      char* end = nullptr;
      errno = 0;
      const unsigned long long count = words.size() == 3 ? std::strtoull(words[2].c_str(), &end, 10) : 0;
      if (words.size() != 3 || words[2][0] == '-' || errno != 0 || end != words[2].c_str() + words[2].size()) {
        fail("element line '" + line + "' has no count");
      }
      elements.push_back({words[1], count, 0, {}});
    } else if (words[0] == "property") {
      const bool list = words.size() == 5 && words[1] == "list";
      const int bytes = list ? scalar_bytes(words[2]) : words.size() == 3 ? scalar_bytes(words[1]) : 0;
      if (bytes == 0 || (list && scalar_bytes(words[3]) == 0)) fail("unknown property line '" + line + "'");
      if (elements.empty()) fail("property line '" + line + "' before any element line");
      elements.back().min_binary_bytes += static_cast<unsigned long long>(bytes);
      elements.back().properties.push_back(
          {list, bytes, list ? scalar_bytes(words[3]) : 0, list && IsPlyFloat(words[2])});
    } else if (words[0] != "comment" && words[0] != "obj_info") {
      fail("unknown header line '" + line.substr(0, 40) + "'");
    }
  }
  if (!ended) fail("no end_header line");
  if (!format) fail("no format line");
  const unsigned long long body = size > header_bytes ? size - header_bytes : 0;
  unsigned long long needed = 0;
  for (const PlyElement& e : elements) {
    // An instance takes at least one byte (an element without properties
    // would otherwise be free to declare any count).
    const unsigned long long each = std::max<unsigned long long>(
        1, ascii ? 2 * e.properties.size() - (e.properties.empty() ? 0 : 1) : e.min_binary_bytes);
    if (e.count > body / each || needed > body - e.count * each) {
      fail("declares more elements than its " + std::to_string(body) + " bytes after the header can hold");
    }
    needed += e.count * each;
  }
  PlyLayout layout;
  layout.ascii = ascii;
  layout.big_endian = big_endian;
  layout.header_bytes = header_bytes;
  layout.elements = std::move(elements);
  return layout;
}

[[noreturn]] void FailPlyInstance(const std::string& name, const PlyElement& e, unsigned long long i,
                                  const std::string& what) {
  throw InputErrorAt(name, "malformed PLY file (" + e.name + " " + std::to_string(i) + ": " + what + ")");
}

// One ASCII instance: its line (blank and comment lines skipped), a token per
// property, each list count a non-negative integer its line holds.
void CheckAsciiPlyInstance(std::istream& in, const std::string& name, const PlyElement& e, unsigned long long i) {
  std::vector<std::string> words;
  std::string line;
  while (words.empty() || words[0] == "comment") {
    if (!std::getline(in, line)) FailPlyInstance(name, e, i, "the file ends before it");
    const std::string control = FirstControlCharacter(line);
    if (!control.empty()) FailPlyInstance(name, e, i, "a control character (" + control + ")");
    words.clear();
    std::istringstream tokens(line);
    for (std::string word; tokens >> word;) words.push_back(word);
  }
  std::size_t next = 0;
  for (const PlyProperty& p : e.properties) {
    if (next >= words.size()) FailPlyInstance(name, e, i, "fewer values than properties");
    const std::string& word = words[next++];
    if (!p.list) continue;
    char* end = nullptr;
    errno = 0;
    const unsigned long long count = std::strtoull(word.c_str(), &end, 10);
    if (word[0] == '-' || errno != 0 || end != word.c_str() + word.size() || count > words.size() - next) {
      FailPlyInstance(name, e, i, "a list count '" + word.substr(0, 24) + "' that its line does not hold");
    }
    next += static_cast<std::size_t>(count);
  }
}

// One binary instance, byte by byte: each list count non-negative and its
// items within the `left` bytes of the file not yet read.
void CheckBinaryPlyInstance(std::istream& in, const std::string& name, const PlyElement& e, unsigned long long i,
                            bool big_endian, unsigned long long* left) {
  for (const PlyProperty& p : e.properties) {
    const unsigned long long bytes = static_cast<unsigned long long>(p.bytes);
    if (bytes > *left) FailPlyInstance(name, e, i, "the file ends before it");
    *left -= bytes;
    if (!p.list) {
      in.ignore(static_cast<std::streamsize>(bytes));
      continue;
    }
    unsigned char raw[8] = {};
    in.read(reinterpret_cast<char*>(raw), static_cast<std::streamsize>(bytes));
    const double count = DecodePlyCount(raw, p.bytes, p.float_count, big_endian);
    const unsigned long long item = static_cast<unsigned long long>(p.item_bytes);
    if (!(count >= 0) || count > static_cast<double>(*left / item)) {
      FailPlyInstance(name, e, i, "a list count of " + std::to_string(count) + " items that the file does not hold");
    }
    const unsigned long long items = static_cast<unsigned long long>(count) * item;
    in.ignore(static_cast<std::streamsize>(items));
    *left -= items;
  }
  if (!in) FailPlyInstance(name, e, i, "the file ends before it");
}

// The list counts of a PLY body, checked before assimp reads it: assimp 5.2
// sizes a list by its count before reading it (fuzz_mesh found an ASCII face
// "7777...73 0 1 3" making it allocate 15 GB; a binary uint count can
// declare 4 billion). ASCII: one instance per line (blank lines skipped), a
// token per property, each list count a non-negative integer with at least
// that many tokens after it on its line. Binary: the instances walked byte by
// byte, each list count non-negative and its items within the file.
void CheckPlyBody(const fs::path& path, const std::string& name, const PlyLayout& layout) {
  std::ifstream in(path, std::ios::binary);
  if (!in || !in.ignore(static_cast<std::streamsize>(layout.header_bytes))) {
    throw InputErrorAt(name, "cannot read mesh (cannot open file)");
  }
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  unsigned long long left = size > layout.header_bytes ? size - layout.header_bytes : 0;  // binary bytes not yet read
  for (const PlyElement& e : layout.elements) {
    const bool has_list =
        std::any_of(e.properties.begin(), e.properties.end(), [](const PlyProperty& p) { return p.list; });
    if (!layout.ascii && !has_list) {  // fixed-size instances (vertices): skipped in one step
      if (e.count > left / std::max<unsigned long long>(1, e.min_binary_bytes)) {
        FailPlyInstance(name, e, 0, "the file ends before it");
      }
      left -= e.count * e.min_binary_bytes;
      in.ignore(static_cast<std::streamsize>(e.count * e.min_binary_bytes));
      continue;
    }
    for (unsigned long long i = 0; i < e.count; ++i) {
      if (layout.ascii) {
        CheckAsciiPlyInstance(in, name, e, i);
      } else {
        CheckBinaryPlyInstance(in, name, e, i, layout.big_endian, &left);
      }
    }
  }
}

// Reads the file with the importer as set up, checks the raw import, and
// collects the nodes.
MeshFile ImportWithAssimp(Assimp::Importer& importer, const std::string& name) {
  // Read without post-processing first: the raw vertices are checked before
  // aiProcess_JoinIdenticalVertices, which mangles NaN vertices (NaN never
  // compares equal, so they get merged into or dropped for others).
  const aiScene* scene = importer.ReadFile(name, 0);
  if (scene != nullptr) {
    CheckRawScene(*scene, name);
    scene =
        importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  }
  if (scene == nullptr) {
    std::string why = importer.GetErrorString();
    for (char& c : why) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    while (!why.empty() && why.back() == ' ') why.pop_back();
    if (why.empty()) why = "unknown assimp error";
    throw InputErrorAt(name, "cannot read mesh (" + why + ")");
  }

  MeshFile file;
  BadVertex bad;
  if (scene->mRootNode != nullptr) {
    try {
      std::vector<std::string> ancestors;
      std::size_t vertex_count = 0;
      CollectNode(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), ancestors, file, vertex_count, bad);
    } catch (const InputError& e) {
      throw InputErrorAt(name, e.what());
    }
  }
  for (std::size_t n = 0; n < file.nodes.size(); ++n) {
    if (!file.nodes[n].mesh.triangles.empty()) file.parts.push_back(static_cast<int>(n));
  }
  if (file.parts.empty()) throw InputErrorAt(name, "mesh has no triangles");
  if (bad.index >= 0) {
    // The index is 0-based in the loaded mesh (after assimp's vertex joining).
    throw InputErrorAt(name, BadVertexText(bad.index, bad.value));
  }
  return file;
}

// A MeshFile as bytes, for ImportWithAssimp in a child process to hand its
// result back: every number in its binary form, so the file arrives exactly.
void PutCount(std::string& out, std::size_t n) { out.append(reinterpret_cast<const char*>(&n), sizeof n); }
void PutText(std::string& out, const std::string& text) {
  PutCount(out, text.size());
  out += text;
}
void PutTexts(std::string& out, const std::vector<std::string>& texts) {
  PutCount(out, texts.size());
  for (const std::string& text : texts) PutText(out, text);
}
template <typename T>
void PutArray(std::string& out, const std::vector<T>& items) {
  PutCount(out, items.size());
  if (!items.empty()) out.append(reinterpret_cast<const char*>(items.data()), items.size() * sizeof(T));
}

std::string MeshFileBytes(const MeshFile& file) {
  std::string out;
  PutCount(out, file.nodes.size());
  for (const MeshPart& node : file.nodes) {
    PutText(out, node.name);
    PutText(out, node.node_name);
    PutTexts(out, node.mesh_names);
    PutTexts(out, node.groups);
    PutArray(out, node.mesh.vertices);
    PutArray(out, node.mesh.triangles);
  }
  PutArray(out, file.parts);
  PutTexts(out, file.also_read);
  return out;
}

class MeshFileBytesReader {
 public:
  explicit MeshFileBytesReader(std::string_view bytes) : bytes_(bytes) {}

  MeshFile Read() {
    MeshFile file;
    file.nodes.resize(Count(1));
    for (MeshPart& node : file.nodes) {
      node.name = Text();
      node.node_name = Text();
      node.mesh_names = Texts();
      node.groups = Texts();
      Array(node.mesh.vertices);
      Array(node.mesh.triangles);
    }
    Array(file.parts);
    file.also_read = Texts();
    if (pos_ != bytes_.size()) throw std::runtime_error("mesh import: bytes left over from the child process");
    return file;
  }

 private:
  // A count, checked against the bytes left (each item at least
  // `item_bytes`) before anything is sized by it.
  std::size_t Count(std::size_t item_bytes) {
    std::size_t n = 0;
    Take(&n, sizeof n);
    if (n > (bytes_.size() - pos_) / std::max<std::size_t>(item_bytes, 1)) {
      throw std::runtime_error("mesh import: truncated result from the child process");
    }
    return n;
  }
  void Take(void* to, std::size_t size) {
    if (size > bytes_.size() - pos_) throw std::runtime_error("mesh import: truncated result from the child process");
    if (size == 0) return;  // `to` may be null (an empty vector's data)
    std::memcpy(to, bytes_.data() + pos_, size);
    pos_ += size;
  }
  std::string Text() {
    std::string text(Count(1), '\0');
    Take(text.data(), text.size());
    return text;
  }
  std::vector<std::string> Texts() {
    std::vector<std::string> texts(Count(sizeof(std::size_t)));
    for (std::string& text : texts) text = Text();
    return texts;
  }
  template <typename T>
  void Array(std::vector<T>& items) {
    items.resize(Count(sizeof(T)));
    Take(items.data(), items.size() * sizeof(T));
  }

  std::string_view bytes_;
  std::size_t pos_ = 0;
};

// The file parsed by assimp, after our structure checks (LoadMeshFile).
MeshFile ParseMeshFile(const fs::path& path) {
  const std::string name = path.string();
  // assimp's logging is off unless a DefaultLogger is created; none is.
  Assimp::Importer importer;
  // assimp picks its importer by the extension; for an unknown one it tries
  // every importer on the content, which for some text takes minutes. Only
  // the formats assimp names are read.
  const std::string extension = path.extension().string();
  std::string lower = extension;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // assimp takes a STEP file for IFC (the same file syntax) and says "IFC:
  // Unrecognized file schema: AUTOMOTIVE_DESIGN": a CAD model is no mesh.
  // Its solids are tessellated once by ausbau-assembly (OpenCASCADE, a
  // layer above this one), not by every stage that loads the scene.
  if (lower == ".step" || lower == ".stp" || lower == ".p21") {
    throw InputErrorAt(name, "cannot read mesh (a STEP file is a CAD model, not a mesh: `ausbau-assembly --assembly " +
                                 path.filename().string() +
                                 " -o DIR` tessellates it and writes a scene per part, which reads DIR/" +
                                 path.stem().string() + ".tessellated.obj)");
  }
  if (lower == ".igs" || lower == ".iges") {
    throw InputErrorAt(name,
                       "cannot read mesh (an IGES file is a CAD model, not a mesh: export STEP and run "
                       "ausbau-assembly on it, or export a mesh: .obj, .stl, .ply)");
  }
  if (extension.empty() || !importer.IsExtensionSupported(extension.c_str())) {
    throw InputErrorAt(name, "cannot read mesh (unknown format '" + extension +
                                 "': expected a format assimp reads, e.g. .obj, .stl, .ply, .off, .dae)");
  }
  if (lower == ".obj") {
    CheckObjStructure(path, name);
    importer.SetIOHandler(new OnlyThisFile(name));  // the importer owns it
  }
  if (lower == ".off") CheckOffStructure(path, name);
  if (lower == ".ply") CheckPlyBody(path, name, ReadPlyHeader(path, name));
  // OBJ, PLY and OFF pass our structure checks first, and STL's importer is
  // a small one; these four (which fuzz_mesh covers) are read here. Any
  // other format (COLLADA, glTF, ...) is read in a child process: assimp
  // 5.2's COLLADA importer crashes on a malformed file
  // (fuzz/known-findings/), and the rest are not hardened either.
  if (lower == ".obj" || lower == ".ply" || lower == ".off" || lower == ".stl") return ImportWithAssimp(importer, name);
  auto* files = new RegularFilesRecorded(name);
  importer.SetIOHandler(files);  // the importer owns it
  const auto import = [&] {
    try {
      MeshFile file = ImportWithAssimp(importer, name);
      file.also_read = files->opened();
      return file;
    } catch (const InputError&) {
      if (files->refused().empty()) throw;
      throw InputErrorAt(name, "cannot read mesh (it names '" + files->refused() +
                                   "', which is not a regular file: a FIFO, socket or device)");
    }
  };
  // The child may take 1 GiB plus 64 bytes per byte of the file: an XML
  // format's document tree and the meshes take a few times the file (a
  // fuzzed 700-byte COLLADA file made assimp ask for 3 GB).
  const std::size_t allowance = (std::size_t{1} << 30) + 64 * static_cast<std::size_t>(fs::file_size(path));
  const std::string bytes = RunInChildProcess([&] { return MeshFileBytes(import()); }, name,
                                              "the " + lower.substr(1) + " importer of assimp", allowance);
  return MeshFileBytesReader(bytes).Read();
}

// The mesh cache (mesh_io.h, MeshCacheDir): an entry is the parsed MeshFile
// as MeshFileBytes, behind a header that names what it was made from and a
// hash of the bytes that follow, both checked before the entry is trusted.
constexpr char kMeshCacheMagic[] = "ausbau-mesh-cache 1\n";
constexpr std::uintmax_t kMeshCacheMinBytes = std::uintmax_t{1} << 20;

// What an entry is made from: the file's bytes, the extension (which picks
// assimp's importer) and the version of this loader's output.
std::string MeshCacheKey(const fs::path& path, const std::string& lower_extension) {
  return HashString(HashFile(path) + "\n" + lower_extension + "\n" + kMeshCacheMagic);
}

// The entry's MeshFile, or nothing when it is missing, was made from another
// file, or is damaged (then it is rewritten after parsing, with a note).
std::optional<MeshFile> ReadMeshCacheEntry(const fs::path& entry, const std::string& key) {
  std::error_code error;
  if (!fs::is_regular_file(fs::symlink_status(entry, error))) return std::nullopt;
  std::ifstream in(entry, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string magic = kMeshCacheMagic;
  const std::size_t header = magic.size() + 2 * 33;  // key and payload hash, 32 hex digits and '\n' each
  const auto damaged = [&] {
    LogInfo("mesh cache: %s is damaged or incomplete; parsing the mesh again", entry.string().c_str());
    return std::nullopt;
  };
  if (!in.good() && !in.eof()) return damaged();
  if (bytes.size() < header || bytes.compare(0, magic.size(), magic) != 0) return damaged();
  if (bytes.compare(magic.size(), 32, key) != 0) return std::nullopt;  // another file (a hash prefix collision)
  const std::string_view payload = std::string_view(bytes).substr(header);
  if (bytes.compare(magic.size() + 33, 32, HashString(payload)) != 0) return damaged();
  try {
    return MeshFileBytesReader(payload).Read();
  } catch (const std::runtime_error&) {
    return damaged();
  }
}

void WriteMeshCacheEntry(const fs::path& entry, const std::string& key, const MeshFile& file) {
  const std::string payload = MeshFileBytes(file);
  try {
    WriteTextFileAtomically(entry, kMeshCacheMagic + key + "\n" + HashString(payload) + "\n" + payload);
  } catch (const std::exception& e) {
    // A cache that cannot be written costs time, never the answer.
    LogWarn("mesh cache: not written (%s)", e.what());
  }
}

}  // namespace

std::filesystem::path MeshCacheDir() {
  const char* env = std::getenv("AUSBAU_MESH_CACHE");
  return env != nullptr ? fs::path(env) : fs::path();
}

MeshFile LoadMeshFile(const fs::path& path) {
  // Missing, a folder, a FIFO or a device, absurdly large: refused before
  // assimp opens it (a FIFO would block it forever).
  CheckInputFile(path, kMaxMeshFileBytes, "mesh");
  // Only formats that read one file are cached: a glTF's external buffers
  // would have to be in the key too.
  std::string lower = path.extension().string();
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // Files below 1 MiB parse in milliseconds, less than an entry costs.
  const fs::path cache = MeshCacheDir();
  if (cache.empty() || !(lower == ".obj" || lower == ".ply" || lower == ".off" || lower == ".stl") ||
      fs::file_size(path) < kMeshCacheMinBytes) {
    return ParseMeshFile(path);
  }
  const std::string key = MeshCacheKey(path, lower);
  const fs::path entry = cache / ("mesh-" + key + ".bin");
  if (std::optional<MeshFile> cached = ReadMeshCacheEntry(entry, key)) return std::move(*cached);
  MeshFile file = ParseMeshFile(path);
  WriteMeshCacheEntry(entry, key, file);
  return file;
}

TriangleMesh MeshFile::Merged() const {
  TriangleMesh mesh;
  std::size_t vertices = 0, triangles = 0;
  for (const MeshPart& node : nodes) {
    vertices += node.mesh.vertices.size();
    triangles += node.mesh.triangles.size();
  }
  mesh.vertices.reserve(vertices);
  mesh.triangles.reserve(triangles);
  for (const MeshPart& node : nodes) mesh.Append(node.mesh);
  return mesh;
}

TriangleMesh LoadMesh(const fs::path& path) { return LoadMeshFile(path).Merged(); }

std::vector<int> PickParts(const MeshFile& file, const std::vector<PartPick>& picks) {
  const int count = static_cast<int>(file.parts.size());
  std::vector<bool> picked(file.parts.size(), false);
  for (const PartPick& pick : picks) {
    if (pick.index >= 0) {
      if (pick.index >= count) {
        throw InputError("part " + std::to_string(pick.index) + " is out of range (the file has " +
                         std::to_string(count) + (count == 1 ? " part: " : " parts: ") + PartListText(file) + ")");
      }
      picked[pick.index] = true;
      continue;
    }
    // The part's own name first, then a group above it, then a mesh's name:
    // the most specific meaning a name can have in the file.
    bool found = false;
    for (int k = 0; k < count; ++k) {
      if (file.Part(k).name == pick.name) picked[k] = found = true;
    }
    const auto pick_where = [&](const std::function<const std::vector<std::string>&(const MeshPart&)>& names) {
      for (int k = 0; k < count; ++k) {
        const std::vector<std::string>& list = names(file.Part(k));
        if (std::find(list.begin(), list.end(), pick.name) != list.end()) picked[k] = found = true;
      }
    };
    if (!found) pick_where([](const MeshPart& part) -> const std::vector<std::string>& { return part.groups; });
    if (!found) pick_where([](const MeshPart& part) -> const std::vector<std::string>& { return part.mesh_names; });
    if (!found) throw InputError("part '" + pick.name + "' not found (parts: " + PartListText(file) + ")");
  }
  std::vector<int> out;
  for (int k = 0; k < count; ++k) {
    if (picked[k]) out.push_back(k);
  }
  return out;
}

std::string PartListText(const MeshFile& file, std::size_t limit) {
  std::string text;
  for (std::size_t k = 0; k < file.parts.size() && k < limit; ++k) {
    const std::string& name = file.Part(static_cast<int>(k)).name;
    text += (k > 0 ? ", " : "") + std::to_string(k) + " " + (name.empty() ? "(unnamed)" : name);
  }
  if (file.parts.size() > limit) text += ", ... (" + std::to_string(file.parts.size() - limit) + " more)";
  return text;
}

void SaveObj(const TriangleMesh& mesh, const fs::path& path) {
  std::string text = "# " + std::to_string(mesh.vertices.size()) + " vertices, " +
                     std::to_string(mesh.triangles.size()) + " triangles\n";
  char line[128];
  for (const auto& v : mesh.vertices) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", v.x(), v.y(), v.z());
    text += line;
  }
  for (const auto& t : mesh.triangles) {
    std::snprintf(line, sizeof line, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
    text += line;
  }
  WriteTextFileAtomically(path, text);
}

void SaveObjParts(const std::vector<ObjPart>& parts, const fs::path& path, const std::vector<std::string>& header) {
  std::string text;
  for (std::string line : header) {
    // A comment stays one line (a file name may hold a line break).
    for (char& c : line)
      if (static_cast<unsigned char>(c) < 0x20) c = '?';
    text += "# " + line + "\n";
  }
  char line[128];
  long long first = 1;
  for (const ObjPart& part : parts) {
    if (part.name.empty()) throw std::runtime_error("SaveObjParts: a part without a name");
    for (const char c : part.name) {
      const auto u = static_cast<unsigned char>(c);
      if (!(std::isalnum(u) || c == '.' || c == '_' || c == '-')) {
        throw std::runtime_error("SaveObjParts: part name '" + part.name + "' is not safe for OBJ");
      }
    }
    text += "o " + part.name + "\n";
    for (const auto& v : part.mesh->vertices) {
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", v.x(), v.y(), v.z());
      text += line;
    }
    for (const auto& t : part.mesh->triangles) {
      std::snprintf(line, sizeof line, "f %lld %lld %lld\n", t[0] + first, t[1] + first, t[2] + first);
      text += line;
    }
    first += static_cast<long long>(part.mesh->vertices.size());
  }
  WriteTextFileAtomically(path, text);
}

}  // namespace ausbau
