// Test helper for the report's browser tests (not installed):
//
//   ausbau_test_report_helper offset SCENE.yaml OUT_DIR cx cy cz
//       the same scene with D's mesh moved by c and no dynamic_origin, so the
//       reference point (D's AABB centre) differs from dynamic_origin (0) and
//       the report's interpolation about reference_point is really exercised
//       (the world placement of D is unchanged)
//   ausbau_test_report_helper labels SCENE.yaml LABELS.h5
//       a labels artifact (schema ausbau-labels 1, provisional):
//       deformability = position of each vertex of D along D's longest axis
//   ausbau_test_report_helper big-scene OUT_DIR TRIANGLES
//       a large scene: S a finely tessellated sphere shell (radius 10) open at
//       the top, with about TRIANGLES triangles; D a subdivided rod (about
//       2,000 triangles) inside it; no goal (disassembly)
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include "artifact/artifact.h"
#include "core/hash.h"
#include "labeling/pbd_label.h"
#include "report/report.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

int Offset(const fs::path& in, const fs::path& out_dir, const Eigen::Vector3d& c) {
  const Scene scene = LoadScene(in);
  fs::create_directories(out_dir);
  TriangleMesh part = scene.dynamic_mesh;
  for (auto& v : part.vertices) v += c;
  SaveObj(part, out_dir / "part.obj");
  SaveObj(scene.static_mesh, out_dir / "environment.obj");
  Scene out = scene;
  out.static_files = {out_dir / "environment.obj"};
  out.dynamic_file = out_dir / "part.obj";
  out.dynamic_origin_given = false;
  out.dynamic_origin.setZero();
  // R (x - o) + t = R ((x + c) - 0) + t'  =>  t' = t - R (o + c)
  auto convert = [&](Pose p) {
    p.t -= p.q * (scene.dynamic_origin + c);
    return p;
  };
  out.start = convert(scene.start);
  if (scene.goal) out.goal = convert(*scene.goal);
  out.bounds.reset();
  SaveSceneYaml(out, out_dir / "scene.yaml");
  return 0;
}

int Labels(const fs::path& scene_file, const fs::path& output) {
  const Scene scene = LoadScene(scene_file);
  const Aabb box = scene.dynamic_mesh.Bounds();
  int axis = 0;
  box.Size().maxCoeff(&axis);
  const double extent = box.Size()[axis] > 0 ? box.Size()[axis] : 1.0;
  LabelsArtifact labels;
  labels.measure = "test: position along D's longest axis";
  for (const auto& v : scene.dynamic_mesh.vertices) {
    labels.deformability.push_back((v[axis] - box.min[axis]) / extent);
  }
  labels.displacement = labels.deformability;
  Provenance provenance{"ausbau-test-report-helper", AUSBAU_VERSION, "", {}};
  provenance.inputs.emplace_back("scene", HashFile(scene.file));
  WriteLabelsArtifact(output, labels, provenance);
  return 0;
}

// A grid-subdivided box: n x n quads per face.
TriangleMesh SubdividedBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max, int n) {
  TriangleMesh mesh;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const int base = static_cast<int>(mesh.vertices.size());
      for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
          Eigen::Vector3d p;
          p[axis] = side ? max[axis] : min[axis];
          p[u] = min[u] + (max[u] - min[u]) * i / n;
          p[w] = min[w] + (max[w] - min[w]) * j / n;
          mesh.vertices.push_back(p);
        }
      }
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const int a = base + i * (n + 1) + j, b = a + n + 1;
          if (side) {
            mesh.triangles.push_back({a, b, b + 1});
            mesh.triangles.push_back({a, b + 1, a + 1});
          } else {
            mesh.triangles.push_back({a, b + 1, b});
            mesh.triangles.push_back({a, a + 1, b + 1});
          }
        }
      }
    }
  }
  return mesh;
}

int BigScene(const fs::path& out_dir, long triangles) {
  fs::create_directories(out_dir);
  // Sphere shell, polar angle from 35 degrees (the opening) to 180.
  const double radius = 10, theta0 = 35.0 * M_PI / 180.0;
  const int segments = std::max(16, static_cast<int>(std::sqrt(triangles * 0.65)));
  const int rings = std::max(8, static_cast<int>(triangles / (2.0 * segments)));
  TriangleMesh shell;
  for (int i = 0; i <= rings; ++i) {
    const double theta = theta0 + (M_PI - theta0) * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * M_PI * j / segments;
      // y is up: the opening is at the top.
      shell.vertices.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::cos(theta),
                                  radius * std::sin(theta) * std::sin(phi));
    }
  }
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      const int c = a + segments, d = b + segments;
      shell.triangles.push_back({a, c, d});
      shell.triangles.push_back({a, d, b});
    }
  }
  SaveObj(shell, out_dir / "environment.obj");
  SaveObj(SubdividedBox({-2, -0.5, -0.5}, {2, 0.5, 0.5}, 13), out_dir / "part.obj");
  Scene scene;
  scene.name = "big-sphere";
  scene.units = "mm";
  scene.static_files = {out_dir / "environment.obj"};
  scene.dynamic_file = out_dir / "part.obj";
  scene.start.t = Eigen::Vector3d(0, -4, 0);
  scene.up_axis = "y";  // the shell opens upwards along y; OBJ alone would say z
  SaveSceneYaml(scene, out_dir / "scene.yaml");
  std::printf("S %zu triangles, D %zu triangles\n", shell.triangles.size(), 13 * 13 * 12ul);
  return 0;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  const std::string command = argc > 1 ? argv[1] : "";
  try {
    if (command == "offset" && argc == 7) {
      return Offset(argv[2], argv[3], {std::stod(argv[4]), std::stod(argv[5]), std::stod(argv[6])});
    }
    if (command == "labels" && argc == 4) return Labels(argv[2], argv[3]);
    if (command == "big-scene" && argc == 4) return BigScene(argv[2], std::stol(argv[3]));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", argv[0], e.what());
    return 2;
  }
  std::fprintf(stderr,
               "usage: %s offset SCENE.yaml OUT_DIR cx cy cz | labels SCENE.yaml LABELS.h5 | "
               "big-scene OUT_DIR TRIANGLES\n",
               argv[0]);
  return 2;
}
