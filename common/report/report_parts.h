// Names for the parts of D and S in a report: the mesh file, the assimp
// node (and mesh) the triangles came from, and the shell (connected solid,
// geometry/shells.h) where the rigid-depth model split the mesh, e.g.
// "static.obj › bracket/Mesh_2 (shell 3)". Replaces bare component numbers.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "collision/rigid_depth.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau::report_internal {

class PartNamer {
 public:
  // Reads the node names of D's and S's files again (LoadMesh with parts);
  // `shells`: the shells of D and S in the scene's triangle order (null:
  // no shell numbers). A file whose parts do not add up to the scene's
  // triangles (it changed since) is named by its file name only.
  PartNamer(const Scene& scene, std::shared_ptr<const PartModel> shells);

  // A triangle of D (robot = true) or S, as "file › node (shell k)"; "–"
  // for -1.
  std::string Triangle(int triangle, bool robot) const;
  // A shell of the rigid-depth model, by the name of its first triangle.
  std::string Shell(int shell, bool robot) const;

 private:
  struct Range {
    int first = 0, count = 0;
    std::string name;
  };
  std::string Base(int triangle, bool robot) const;
  // Appends the ranges of one file starting at triangle `first`; returns its
  // triangle count (-1 where it cannot be read).
  static int AddFile(const std::filesystem::path& file, int first, std::vector<Range>* ranges);

  std::vector<Range> dynamic_ranges_, static_ranges_;
  std::vector<int> dynamic_shell_, static_shell_;  // per triangle; empty without shells
  std::shared_ptr<const PartModel> shells_;
};

}  // namespace ausbau::report_internal
