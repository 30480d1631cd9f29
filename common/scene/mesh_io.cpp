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
#include <stdexcept>
#include <string>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"

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

// The first vertex that is not finite, as read from the file.
struct BadVertex {
  long index = -1;  // in the loaded mesh
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
};

// Emits the triangles of every mesh of `node` and its descendants.
void CollectNode(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent, TriangleMesh& out,
                 BadVertex& bad) {
  const Eigen::Matrix4d transform = parent * ToEigen(node.mTransformation);
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    const unsigned mesh_index = node.mMeshes[k];
    if (mesh_index >= scene.mNumMeshes || scene.mMeshes[mesh_index] == nullptr) continue;
    const aiMesh& mesh = *scene.mMeshes[mesh_index];
    const int offset = static_cast<int>(out.vertices.size());
    out.vertices.reserve(out.vertices.size() + mesh.mNumVertices);
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D& p = mesh.mVertices[i];
      const Eigen::Vector4d h(p.x, p.y, p.z, 1.0);
      const Eigen::Vector4d w = transform * h;
      if (bad.index < 0 && !(h.allFinite() && w.allFinite())) {
        bad.index = static_cast<long>(out.vertices.size());
        bad.value = h.allFinite() ? Eigen::Vector3d(w.head<3>()) : Eigen::Vector3d(h.head<3>());
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
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputErrorAt(name, "file not found");
  if (fs::is_directory(path, ec)) throw InputErrorAt(name, "cannot read mesh (is a directory)");

  // assimp's logging is off unless a DefaultLogger is created; none is.
  Assimp::Importer importer;
  // Read without post-processing first: the raw vertices are checked before
  // aiProcess_JoinIdenticalVertices, which mangles NaN vertices (NaN never
  // compares equal, so they get merged into or dropped for others).
  const aiScene* scene = importer.ReadFile(name, 0);
  if (scene != nullptr) {
    long index = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
      const aiMesh* mesh = scene->mMeshes[m];
      if (mesh == nullptr) continue;
      for (unsigned i = 0; i < mesh->mNumVertices; ++i, ++index) {
        const aiVector3D& p = mesh->mVertices[i];
        const Eigen::Vector3d v(p.x, p.y, p.z);
        if (!v.allFinite()) {
          // 0-based, counting the vertices of all meshes of the file in order
          // as the importer produced them (before vertex joining).
          throw InputErrorAt(name, "vertex " + std::to_string(index) + " is not finite (" + FormatVertex(v) + ")");
        }
      }
    }
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
    CollectNode(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), mesh, bad);
  }
  if (mesh.triangles.empty()) throw InputErrorAt(name, "mesh has no triangles");
  if (bad.index >= 0) {
    // The index is 0-based in the loaded mesh (after assimp's vertex joining).
    throw InputErrorAt(name,
                       "vertex " + std::to_string(bad.index) + " is not finite (" + FormatVertex(bad.value) + ")");
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
