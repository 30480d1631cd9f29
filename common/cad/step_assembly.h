// STEP assemblies in (AP203, AP214, AP242), through OpenCASCADE's XCAF: the
// product tree with its names and placements, every leaf part tessellated
// once and placed by each of its instances, in millimetres.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "core/log.h"
#include "geometry/mesh.h"

namespace ausbau {

// Whether a file name has a STEP extension (.step, .stp, .p21; any case).
bool IsStepFileName(const std::filesystem::path& path);

struct StepTessellation {
  // The chord error: no point of a triangle is farther than this from the
  // CAD surface (mm, absolute). Default 0.02 mm, below the default rigid
  // tolerance (0.05 mm): two surfaces that touch in CAD then overlap by at
  // most this after tessellation (a bore's polygon lies inside the bore,
  // the pin's vertices on its surface), which counts as contact, not as an
  // interference (README "STEP assemblies").
  double deflection_mm = 0.02;
  // The largest angle between the normals of neighbouring triangles of a
  // curved face (radians); OpenCASCADE's default.
  double angular_deflection_rad = 0.5;
  // The products tessellated of those with a shape (core/log.h; from the
  // child process that reads the file, on its stderr); empty = silent.
  ProgressCallback progress;
};

// One leaf instance of the product tree: a part placed in the assembly.
struct StepPart {
  std::string name;               // the instance's name, else its product's name; may be empty, may repeat
  std::string product;            // its product's (shape's) name; may be empty
  std::vector<std::string> path;  // names from the root's down to this instance's (the product tree)
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();  // the instance in the world (mm)
  TriangleMesh mesh;                // world coordinates (mm), welded where faces share a vertex exactly
  int faces = 0;                    // CAD faces of the part
  int faces_without_triangles = 0;  // faces OpenCASCADE could not tessellate (left out)
  // Faces OpenCASCADE tessellated only with a coarser interior than the
  // chord error asked for (up to 16x; their edges at it), and an upper
  // bound of those faces' chord error measured on their triangles (mm).
  int faces_meshed_coarser = 0;
  double coarser_chord_error_mm = 0;
  // The area (mm^2, the product's own) of its triangles that lie on another
  // face of the same solid: 0 for a valid tessellation; more, a face was
  // tessellated beyond its boundary (the mesh is not the part there).
  double overlapping_surface_mm2 = 0;
};

struct StepAssembly {
  std::string file_units;       // the file's length unit as it names it ("millimetre", "inch", ...); may be empty
  std::vector<StepPart> parts;  // depth-first, in the file's order
  int products = 0;             // distinct leaf products (shapes tessellated once each)
};

// Reads and tessellates a STEP file. Throws InputError ("<file>: <problem>")
// when the file is missing, not a regular file, not STEP, holds no shape,
// or no triangle after tessellation, or when a deflection is not a finite
// positive number.
StepAssembly ReadStepAssembly(const std::filesystem::path& path, const StepTessellation& tessellation);

}  // namespace ausbau
