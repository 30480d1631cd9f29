// A flange-like narrow-passage scene generated in code, in the spirit of the
// Parasol "Flange" problem the thesis benchmarks in three clearances
// (Flange 1.0, 0.95, 0.9: the tube's diameter shrunk by 0 / 5 / 10 %).
//
// S: a square plate (14 x 14, 1 thick, in the xy-plane about z = 0) with a
// round hole (64-gon) about the z axis.
// D: a bent tube (a 90 degree elbow between two straight legs) with a flange
// disc at the end of its upper leg. At the start the middle of the elbow
// passes through the hole. The only way out is to slide the elbow through
// the hole by turning D about the elbow's axis (a screw-like motion for the
// planner, whose reference point is D's AABB centre) until the lower leg
// stands in the hole, then to pull it out upwards; the flange blocks the
// other direction. At scale 1.0 the radial clearance in the hole is about
// 2.6% of the tube's radius; at 0.95 and 0.9 about 8% and 14%.
// Both meshes are closed and consistently oriented (the flange is a
// separate closed solid overlapping the tube's end).
#pragma once

#include <filesystem>
#include <string>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

struct FlangeScene {
  TriangleMesh environment;  // S, world coordinates
  TriangleMesh part;         // D, in its mesh coordinates; the start pose is the identity
  Pose start;
  std::string name;          // "flange-1.00", ...
};

// `scale` is the tube diameter factor, in [0.5, 1.0] (1.0, 0.95 and 0.9
// reproduce the thesis's three difficulties). Throws InputError otherwise.
FlangeScene MakeFlangeScene(double scale);

// Writes <dir>/scene.yaml, <dir>/environment.obj, <dir>/part.obj (no goal:
// a disassembly problem; bounds derived) and returns the scene.yaml path.
std::filesystem::path GenerateFlangeScene(double scale, const std::filesystem::path& dir);

}  // namespace ausbau
