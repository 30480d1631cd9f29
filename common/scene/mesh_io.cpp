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
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>

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
void CollectNode(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent, TriangleMesh& out,
                 BadVertex& bad) {
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
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    if (node.mChildren[c] != nullptr) CollectNode(scene, *node.mChildren[c], transform, out, bad);
  }
}

}  // namespace

TriangleMesh LoadMesh(const fs::path& path) {
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
      CollectNode(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), mesh, bad);
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
