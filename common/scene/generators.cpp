#include "scene/generators.h"

#include "core/error.h"
#include "geometry/primitives.h"
#include "planning/random.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

struct Generated {
  TriangleMesh environment, part;
  Pose start;
  std::optional<Pose> goal;
  std::optional<Aabb> bounds;
  std::string description;
};

// A closed cage (10 x 10 x 10 inside, walls 1 thick) with a slot in its lid;
// inside lies a rod longer than the slot is wide, across the slot. The rod
// must turn by about 90 degrees about z before it can leave through the slot.
Generated RodInCage(Random& random) {
  Generated g;
  const double inner = 5.0, wall = 1.0;
  const double slot_long = 4.2 + 0.2 * random.Uniform01(), slot_short = 1.0;
  g.environment.Append(MakeBox({-inner - wall, -inner - wall, -inner - wall}, {inner + wall, inner + wall, -inner}));
  g.environment.Append(MakeBox({-inner - wall, -inner - wall, -inner}, {-inner, inner + wall, inner}));
  g.environment.Append(MakeBox({inner, -inner - wall, -inner}, {inner + wall, inner + wall, inner}));
  g.environment.Append(MakeBox({-inner, -inner - wall, -inner}, {inner, -inner, inner}));
  g.environment.Append(MakeBox({-inner, inner, -inner}, {inner, inner + wall, inner}));
  g.environment.Append(MakePlateWithRectHole(inner + wall, inner + wall, slot_long, slot_short, 0, 0, inner, inner + wall));
  // The rod along y: 7 long, 1.2 thick; the slot is 2 wide in y, ~8.5 long in x.
  const double half_length = 3.5, half_thickness = 0.6;
  g.part = MakeBox({-half_thickness, -half_length, -half_thickness}, {half_thickness, half_length, half_thickness});
  g.start.t = {0.0, 0.0, -2.0};
  g.description = "rod in a cage with a slotted lid: turn about z, then lift";
  return g;
}

// A plate with a square hole and a square peg through it: pull it out along z.
Generated PegInPlate(Random& random) {
  Generated g;
  const double hole = 1.0 + 0.05 * random.Uniform01();
  g.environment = MakePlateWithHole(6.0, hole, -0.5, 0.5);
  g.part = MakeBox({-0.9, -0.9, -3.0}, {0.9, 0.9, 3.0});
  g.start.t = {0.0, 0.0, 0.0};
  g.description = "square peg through a plate with a square hole";
  return g;
}

// Two boxes side by side; a goal pose on the other side of the static box.
Generated TwoBoxes(Random& random) {
  Generated g;
  const double size = 1.0 + 0.1 * random.Uniform01();
  g.environment = MakeBox({-size, -size, -size}, {size, size, size});
  g.part = MakeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
  g.start.t = {-3.0, 0.0, 0.0};
  Pose goal;
  goal.t = {3.0, 0.0, 0.0};
  goal.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  g.goal = goal;
  Aabb bounds;
  bounds.min = {-5, -5, -5};
  bounds.max = {5, 5, 5};
  g.bounds = bounds;
  g.description = "two boxes: go around the static one to a goal pose";
  return g;
}

}  // namespace

std::vector<std::string> GeneratedSceneFamilies() { return {"rod-in-cage", "peg-in-plate", "two-boxes"}; }

std::filesystem::path GenerateScene(const std::string& family, std::uint64_t seed, const std::filesystem::path& dir) {
  Random random(seed);
  Generated g;
  if (family == "rod-in-cage") {
    g = RodInCage(random);
  } else if (family == "peg-in-plate") {
    g = PegInPlate(random);
  } else if (family == "two-boxes") {
    g = TwoBoxes(random);
  } else {
    throw InputError("--family: unknown family '" + family + "' (expected rod-in-cage, peg-in-plate or two-boxes)");
  }
  std::filesystem::create_directories(dir);
  Scene scene;
  scene.name = family + "-" + std::to_string(seed);
  scene.units = "mm";
  scene.static_files = {dir / "environment.obj"};
  scene.dynamic_file = dir / "part.obj";
  scene.dynamic_origin = Eigen::Vector3d::Zero();
  scene.dynamic_origin_given = true;
  scene.start = g.start;
  scene.goal = g.goal;
  scene.bounds = g.bounds;
  SaveObj(g.environment, scene.static_files[0]);
  SaveObj(g.part, scene.dynamic_file);
  const std::filesystem::path yaml = dir / "scene.yaml";
  SaveSceneYaml(scene, yaml);
  return yaml;
}

}  // namespace ausbau
