#include "labeling/solid_labels.h"

#include <algorithm>
#include <cmath>

#include "collision/rigid_depth.h"
#include "collision/scene_parts.h"
#include "core/format.h"

namespace ausbau {

SolidLabels LabelBySolids(const Scene& scene, double tolerance) {
  SolidLabels out;
  const auto parts = ClassifySceneParts(scene, tolerance, UnmeasuredInterference::kRigid);
  out.solids = static_cast<int>(parts->robot_shells.size());
  for (int shell = 0; shell < out.solids; ++shell) {
    if (!parts->robot_shells[shell].closed) {
      out.reason = "D has an open surface (" + parts->Describe(shell, true) + "): no solids to label";
      return out;
    }
  }
  // A rigid solid that clashes with S at the installed pose (not a fit): a
  // clip moulded into the part, or a part that cannot come out; the rule
  // cannot split one solid, so it leaves the labels to PBD.
  if (!parts->rigid_interference.empty()) {
    const int shell = parts->rigid_interference.front();
    out.reason =
        Fmt("%s intersects S %.4g deep at the installed pose as one solid (a clip moulded into it?): the "
            "rule cannot split a solid",
            parts->Describe(shell, true).c_str(), parts->installed_depth[shell]);
    return out;
  }
  out.applies = true;
  out.fasteners = parts->FastenerCount();
  out.deformability.assign(scene.dynamic_mesh.vertices.size(), 0.0);
  for (std::size_t s = 0; s < parts->robot_shells.size(); ++s) {
    const auto& source = parts->robot_shells[s].source_triangles;
    // Fasteners moulded into a rigid shell: its triangles in their boxes.
    const DepthMask* mask = parts->Mask(static_cast<int>(s));
    for (std::size_t k = 0; k < source.size(); ++k) {
      if (parts->role[s] != ShellRole::kFastener && !(mask && mask->skip_triangle[k])) continue;
      for (int v : scene.dynamic_mesh.triangles[source[k]]) out.deformability[v] = 1.0;
    }
  }
  out.reason = std::to_string(out.solids) + " closed solids, " + std::to_string(out.fasteners) +
               " of them intersecting S at the installed pose (or overlapping one that does): fasteners";
  if (!parts->moulded.empty())
    out.reason += " (" + std::to_string(parts->moulded.size()) + " of them moulded into a solid)";
  return out;
}

}  // namespace ausbau
