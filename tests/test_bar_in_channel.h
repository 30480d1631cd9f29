// A hand-checkable scene of a part held in contact, for the what-blocks,
// motion-check and smoothing tests: a bar 2 x 2 x `length` standing in a
// channel as tall as it, whose walls (x = +-(1 - overlap) outwards, 10 wide
// along y) it overlaps by `overlap`, and a floor 0.3 under it; with `bore`
// also walls across y (a square bore: only up is free). S one part.
#pragma once

#include "geometry/primitives.h"
#include "scene/scene.h"

namespace ausbau::testing {

inline Scene BarInChannelScene(double length, double overlap, bool bore = false) {
  const double wall = 1 - overlap;
  Scene scene;
  scene.units = "mm";
  scene.dynamic_mesh = MakeBox({-1, -1, 0}, {1, 1, length});
  scene.static_mesh = MakeBox({wall, -5, 0}, {5, 5, length});
  scene.static_mesh.Append(MakeBox({-5, -5, 0}, {-wall, 5, length}));
  if (bore) {
    scene.static_mesh.Append(MakeBox({-wall, wall, 0}, {wall, 5, length}));
    scene.static_mesh.Append(MakeBox({-wall, -5, 0}, {wall, -wall, length}));
  }
  scene.static_mesh.Append(MakeBox({-5, -5, -3}, {5, 5, -0.3}));
  return scene;
}

}  // namespace ausbau::testing
