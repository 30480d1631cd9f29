// A hand-checkable rigid scene for the rigid-depth and exact-check tests:
// a rigid key (a bar) hanging from a panel into a slot in a 2 mm plate.
#pragma once

#include "geometry/mesh.h"
#include "geometry/primitives.h"

namespace ausbau::testing {

struct KeyScene {
  TriangleMesh robot, environment;
  KeyScene() {
    robot = MakeBox({-50, -50, 5}, {50, 50, 8});        // panel, above the plate
    robot.Append(MakeBox({-2, -10, -10}, {2, 10, 5}));  // key through a slot, 0.5 mm each side in x
    environment = MakeBox({-100, -100, -2}, {-2.5, 100, 0});
    environment.Append(MakeBox({2.5, -100, -2}, {100, 100, 0}));
    environment.Append(MakeBox({-2.5, -100, -2}, {2.5, -11, 0}));
    environment.Append(MakeBox({-2.5, 11, -2}, {2.5, 100, 0}));
  }
};

}  // namespace ausbau::testing
