// ausbau-medial-spheres's work: D's mesh topology (welded, oriented), one
// medial sphere per vertex (thesis alg. 9), logged as it goes, as the
// artifact the stage writes; and D coloured by sphere radius.
#pragma once

#include <filesystem>
#include <string>

#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"
#include "scene/scene.h"

namespace ausbau {

struct PartSpheresOptions {
  MedialSphereOptions spheres;
  double weld_tolerance = MeshTopologyOptions{}.weld_tolerance;  // fraction of D's AABB diagonal
  // Throws InputError naming the flag of a value that does not fit.
  void Check() const;
};

// Throws InputError on options out of range. Shows a progress bar.
SpheresArtifact ComputePartSpheres(const Scene& scene, const PartSpheresOptions& options);

// D as PLY coloured by sphere radius, yellow small to blue large (spheres
// without a radius and contact vertices left out of the colour range).
void WriteSpheresPly(const std::filesystem::path& path, const TriangleMesh& mesh, const SpheresArtifact& spheres);

// ausbau-medial-spheres --csv / --ply (either may be empty: not written):
// x,y,z,radius per vertex of D, and D coloured by sphere radius; logged.
void WriteSpheresExtras(const Scene& scene, const SpheresArtifact& spheres, const std::string& csv,
                        const std::string& ply);

}  // namespace ausbau
