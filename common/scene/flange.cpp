#include "scene/flange.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

// Dimensions (scene units, "mm").
constexpr double kTubeRadius = 1.0;     // at scale 1.0
constexpr double kBendRadius = 4.0;     // radius of the elbow's centre line
constexpr double kBendHalfAngle = M_PI / 4;
constexpr double kLowerLeg = 3.0;
constexpr double kUpperLeg = 4.0;
constexpr double kFlangeRadius = 2.2;
constexpr double kPlateHalfWidth = 7.0;
constexpr double kPlateHalfThickness = 0.5;
constexpr double kHoleRadius = 1.08;    // circumradius of the 64-gon
constexpr int kHoleSegments = 64;       // a multiple of 8: the square's corners are vertices
constexpr int kTubeSegments = 40;
constexpr int kBendRings = 48;

struct Ring {
  Vec3 center, tangent;
};

// A closed tube of circular section swept along rings (planar path in the
// xz-plane, so the y axis is a valid normal everywhere), capped at both ends,
// outward oriented.
void AppendTube(const std::vector<Ring>& rings, double radius, int segments, TriangleMesh* mesh) {
  const int base = static_cast<int>(mesh->vertices.size());
  const Vec3 u = Vec3::UnitY();
  for (const Ring& ring : rings) {
    const Vec3 v = ring.tangent.cross(u).normalized();
    for (int k = 0; k < segments; ++k) {
      const double phi = 2 * M_PI * k / segments;
      mesh->vertices.push_back(ring.center + radius * (std::cos(phi) * u + std::sin(phi) * v));
    }
  }
  auto at = [&](int j, int k) { return base + j * segments + (k % segments); };
  const int n = static_cast<int>(rings.size());
  for (int j = 0; j + 1 < n; ++j) {
    for (int k = 0; k < segments; ++k) {
      mesh->triangles.push_back({at(j, k), at(j, k + 1), at(j + 1, k + 1)});
      mesh->triangles.push_back({at(j, k), at(j + 1, k + 1), at(j + 1, k)});
    }
  }
  const int first = static_cast<int>(mesh->vertices.size());
  mesh->vertices.push_back(rings.front().center);
  mesh->vertices.push_back(rings.back().center);
  for (int k = 0; k < segments; ++k) {
    mesh->triangles.push_back({first, at(0, k + 1), at(0, k)});          // faces -tangent
    mesh->triangles.push_back({first + 1, at(n - 1, k), at(n - 1, k + 1)});  // faces +tangent
  }
}

// The square plate with a round hole, closed and outward oriented.
TriangleMesh MakePlate() {
  TriangleMesh plate;
  const int n = kHoleSegments;
  const double zs[2] = {-kPlateHalfThickness, kPlateHalfThickness};
  // Per level (bottom, top): n hole vertices, then n square-boundary vertices
  // (the hole's rays projected onto the square).
  for (double z : zs) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      plate.vertices.emplace_back(kHoleRadius * std::cos(a), kHoleRadius * std::sin(a), z);
    }
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      const double c = std::cos(a), s = std::sin(a), m = std::max(std::abs(c), std::abs(s));
      plate.vertices.emplace_back(kPlateHalfWidth * c / m, kPlateHalfWidth * s / m, z);
    }
  }
  auto hole = [n](int level, int i) { return level * 2 * n + (i % n); };
  auto rim = [n](int level, int i) { return level * 2 * n + n + (i % n); };
  for (int i = 0; i < n; ++i) {
    // Top (normal +z): counter-clockwise seen from above.
    plate.triangles.push_back({hole(1, i), rim(1, i), rim(1, i + 1)});
    plate.triangles.push_back({hole(1, i), rim(1, i + 1), hole(1, i + 1)});
    // Bottom (normal -z).
    plate.triangles.push_back({hole(0, i), rim(0, i + 1), rim(0, i)});
    plate.triangles.push_back({hole(0, i), hole(0, i + 1), rim(0, i + 1)});
    // Hole wall (normal towards the axis).
    plate.triangles.push_back({hole(0, i), hole(1, i), hole(1, i + 1)});
    plate.triangles.push_back({hole(0, i), hole(1, i + 1), hole(0, i + 1)});
    // Outer wall (normal away from the axis).
    plate.triangles.push_back({rim(0, i), rim(1, i + 1), rim(1, i)});
    plate.triangles.push_back({rim(0, i), rim(0, i + 1), rim(1, i + 1)});
  }
  return plate;
}

}  // namespace

FlangeScene MakeFlangeScene(double scale) {
  if (!(scale >= 0.5 && scale <= 1.0)) {
    throw InputError("flange scene: scale must lie in [0.5, 1] (got " + std::to_string(scale) + ")");
  }
  FlangeScene scene;
  char name[32];
  std::snprintf(name, sizeof name, "flange-%.2f", scale);
  scene.name = name;
  scene.environment = MakePlate();

  // The elbow's centre line: a circle of radius kBendRadius about
  // (-kBendRadius, 0, 0) in the xz-plane, through the hole's centre (the
  // origin) with a vertical tangent there.
  const Vec3 center(-kBendRadius, 0, 0);
  auto point = [&](double theta) { return Vec3(center + kBendRadius * Vec3(std::cos(theta), 0, std::sin(theta))); };
  auto tangent = [](double theta) { return Vec3(-std::sin(theta), 0, std::cos(theta)); };
  const double theta0 = -kBendHalfAngle, theta1 = kBendHalfAngle;
  std::vector<Ring> rings;
  rings.push_back({point(theta0) - kLowerLeg * tangent(theta0), tangent(theta0)});
  for (int j = 0; j <= kBendRings; ++j) {
    const double theta = theta0 + (theta1 - theta0) * j / kBendRings;
    rings.push_back({point(theta), tangent(theta)});
  }
  const Vec3 end = point(theta1) + kUpperLeg * tangent(theta1);
  rings.push_back({end, tangent(theta1)});
  AppendTube(rings, kTubeRadius * scale, kTubeSegments, &scene.part);
  // The flange: a disc across the upper leg's end.
  const Vec3 axis = tangent(theta1);
  AppendTube({{end - 0.3 * axis, axis}, {end + 0.1 * axis, axis}}, kFlangeRadius, kHoleSegments, &scene.part);
  return scene;
}

std::filesystem::path GenerateFlangeScene(double scale, const std::filesystem::path& dir) {
  const FlangeScene flange = MakeFlangeScene(scale);
  std::filesystem::create_directories(dir);
  Scene scene;
  scene.name = flange.name;
  scene.units = "mm";
  scene.static_files = {dir / "environment.obj"};
  scene.dynamic_file = dir / "part.obj";
  scene.start = flange.start;
  SaveObj(flange.environment, scene.static_files[0]);
  SaveObj(flange.part, scene.dynamic_file);
  const std::filesystem::path yaml = dir / "scene.yaml";
  SaveSceneYaml(scene, yaml);
  return yaml;
}

}  // namespace ausbau
