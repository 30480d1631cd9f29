// Which scene an artifact was made from. Every artifact records the content
// hash of each input it was made from (artifact/artifact.h: the root
// attribute "inputs", role -> hash; the scene's roles "scene", "static" or
// "static[i]", "dynamic": scene/scene.h SceneInputFiles). A consumer that
// reads an artifact beside a scene checks those hashes against the scene's
// files, so that labels of another part with the same vertex count, or a
// path of another scene, are refused instead of silently used.
#pragma once

#include <string>

namespace ausbau {

struct Scene;

// Which of the scene's files must match.
enum class MadeFrom {
  kDynamicMesh,  // D's mesh (spheres, labels)
  kMeshes,       // D's and S's meshes (voxels, paths, tau)
};

// Throws InputErrorAt(artifact, ...) naming the scene file whose content hash
// differs from the one the artifact recorded for it. Roles the artifact did
// not record (artifacts written without a scene, older files) are not
// checked: nothing to compare with.
void CheckMadeFrom(const std::string& artifact, const std::string& schema, int schema_version, const Scene& scene,
                   MadeFrom what);

}  // namespace ausbau
