// Mesh loading through assimp and a plain OBJ writer.
//
// The import reproduces OMPL.app's: triangulate, join identical vertices,
// sort by primitive type, then walk the node tree from the root accumulating
// node transforms (parent * child) and emit every mesh of every node with its
// vertices transformed; a mesh referenced by several nodes is emitted once
// per node. The COLLADA importer's up-axis correction (Z_UP files are rotated
// to Y-up through the root node's transform) is kept, as in OMPL.app.
#include "scene/mesh_io.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <Eigen/Core>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_file.h"

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

// Emits the triangles of every mesh of `node` and its descendants.
// A name as a file gave it: assimp's placeholders ("<STL_BINARY>",
// "<OBJRoot>", "$$$DUMMY") and "defaultobject" are no name.
std::string GivenName(const aiString& name) {
  const std::string text(name.C_Str());
  if (text.empty() || text.front() == '<' || text.front() == '$' || text == "defaultobject") return "";
  return text;
}

void CollectNode(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent, TriangleMesh& out,
                 BadVertex& bad, std::vector<MeshPart>* parts) {
  const Eigen::Matrix4d transform = parent * ToEigen(node.mTransformation);
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    const unsigned mesh_index = node.mMeshes[k];
    if (mesh_index >= scene.mNumMeshes || scene.mMeshes[mesh_index] == nullptr) continue;
    const aiMesh& mesh = *scene.mMeshes[mesh_index];
    // Triangles index vertices with int: a file whose nodes instance its
    // meshes past that is refused rather than wrapped.
    if (out.vertices.size() + mesh.mNumVertices > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw InputError("more than 2^31 vertices once every node's meshes are placed");
    }
    const int offset = static_cast<int>(out.vertices.size());
    const int first_triangle = static_cast<int>(out.triangles.size());
    out.vertices.reserve(out.vertices.size() + mesh.mNumVertices);
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D& p = mesh.mVertices[i];
      const Eigen::Vector4d h(p.x, p.y, p.z, 1.0);
      const Eigen::Vector4d w = transform * h;
      if (bad.index < 0 && (Absurd(h.head<3>()) || Absurd(w.head<3>()))) {
        bad.index = static_cast<long>(out.vertices.size());
        bad.value = Absurd(h.head<3>()) ? Eigen::Vector3d(h.head<3>()) : Eigen::Vector3d(w.head<3>());
      }
      out.vertices.push_back(w.head<3>());
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines are dropped
      out.triangles.push_back({offset + static_cast<int>(face.mIndices[0]), offset + static_cast<int>(face.mIndices[1]),
                               offset + static_cast<int>(face.mIndices[2])});
    }
    if (parts != nullptr && static_cast<int>(out.triangles.size()) > first_triangle) {
      const std::string node_name = GivenName(node.mName), mesh_name = GivenName(mesh.mName);
      std::string name = node_name;
      if (!mesh_name.empty() && mesh_name != node_name) name += (name.empty() ? "" : "/") + mesh_name;
      parts->push_back({name, first_triangle, static_cast<int>(out.triangles.size()) - first_triangle});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    if (node.mChildren[c] != nullptr) CollectNode(scene, *node.mChildren[c], transform, out, bad, parts);
  }
}

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
  while (std::getline(in, line)) {
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

}  // namespace

TriangleMesh LoadMesh(const fs::path& path) { return LoadMesh(path, nullptr); }

TriangleMesh LoadMesh(const fs::path& path, std::vector<MeshPart>* parts) {
  if (parts != nullptr) parts->clear();
  const std::string name = path.string();
  // Missing, a folder, a FIFO or a device, absurdly large: refused before
  // assimp opens it (a FIFO would block it forever).
  CheckInputFile(path, kMaxMeshFileBytes, "mesh");

  // assimp's logging is off unless a DefaultLogger is created; none is.
  Assimp::Importer importer;
  // assimp picks its importer by the extension; for an unknown one it tries
  // every importer on the content, which for some text takes minutes. Only
  // the formats assimp names are read.
  const std::string extension = path.extension().string();
  if (extension.empty() || !importer.IsExtensionSupported(extension.c_str())) {
    throw InputErrorAt(name, "cannot read mesh (unknown format '" + extension +
                                 "': expected a format assimp reads, e.g. .obj, .stl, .ply, .off, .dae)");
  }
  std::string lower = extension;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == ".off") CheckOffStructure(path, name);
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

  TriangleMesh mesh;
  BadVertex bad;
  if (scene->mRootNode != nullptr) {
    try {
      CollectNode(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), mesh, bad, parts);
    } catch (const InputError& e) {
      throw InputErrorAt(name, e.what());
    }
  }
  if (mesh.triangles.empty()) throw InputErrorAt(name, "mesh has no triangles");
  if (bad.index >= 0) {
    // The index is 0-based in the loaded mesh (after assimp's vertex joining).
    throw InputErrorAt(name, BadVertexText(bad.index, bad.value));
  }
  return mesh;
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

}  // namespace ausbau
