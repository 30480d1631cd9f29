// The scene of the verdict's and the smoother's in-process tests, small
// enough to check by hand: D, a unit cube (z from 0.5 to 1.5), stands
// between two walls (x in [-2, -1] and [1, 2], y in [-1, 1], z in [0, 2]),
// 0.5 from each; every length in mm.
#pragma once

#include <filesystem>
#include <fstream>

#include "geometry/primitives.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau::testing {

// Writes walls.obj, cube.obj and scene.yaml into `dir` and loads the scene.
inline Scene WriteCubeBetweenWalls(const std::filesystem::path& dir) {
  TriangleMesh walls = MakeBox({-2, -1, 0}, {-1, 1, 2});
  walls.Append(MakeBox({1, -1, 0}, {2, 1, 2}));
  SaveObj(walls, dir / "walls.obj");
  SaveObj(MakeBox({-0.5, -0.5, 0.5}, {0.5, 0.5, 1.5}), dir / "cube.obj");
  std::ofstream(dir / "scene.yaml") << "format: ausbau-scene/1\nstatic: [walls.obj]\ndynamic: cube.obj\nunits: mm\n";
  return LoadScene(dir / "scene.yaml");
}

}  // namespace ausbau::testing
