// ausbau-pbd-label's work: the deformability labels of D's vertices.
//   solids  where D is made of closed solids whose installed intersections
//           with S are all measured exactly (CAD box soups): the exact
//           check's rule, a solid intersecting S deeper than the tolerance
//           (and the solids overlapping it) deformable, the rest rigid
//   pbd     the thesis's simulation (alg. 10): one position based dynamics
//           load case per vertex (or a budget of them) on D's welded mesh
//   auto    solids where that rule applies, else pbd
#pragma once

#include <string>

#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"
#include "labeling/pbd_label.h"
#include "scene/scene.h"

namespace ausbau {

struct LabelPartOptions {
  std::string rule = "auto";                                     // auto | solids | pbd
  double rigid_tolerance_mm = 0.05;                              // solids: converted by the scene's units
  double weld_tolerance = MeshTopologyOptions{}.weld_tolerance;  // fraction of D's AABB diagonal
  PbdLabelOptions pbd;
  // Throws InputError naming the flag of a value that does not fit.
  void Check() const;
};

// The labels of D, from the medial spheres in `spheres_file`
// (ausbau-medial-spheres; they must belong to this D, whose mesh file has
// the content hash `dynamic_hash`, as the stage's provenance records it).
// Logs which rule labelled it and why.
LabelsArtifact LabelPart(const Scene& scene, const std::string& dynamic_hash, const std::string& spheres_file,
                         const LabelPartOptions& options);

// ausbau-pbd-label --csv / --ply (either may be empty: not written):
// x,y,z,deformability per vertex of D, and D coloured by deformability
// (blue rigid to red deformable); logged.
void WriteLabelsExtras(const Scene& scene, const LabelsArtifact& labels, const std::string& csv,
                       const std::string& ply);

}  // namespace ausbau
