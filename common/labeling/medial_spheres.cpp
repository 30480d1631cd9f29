#include "labeling/medial_spheres.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/error.h"

namespace ausbau {

void MedialSphereOptions::Check() const {
  if (!(delta > 0 && delta < 1))
    throw OptionError(&delta, "delta", "must lie in (0, 1) (a fraction of D's AABB diagonal)");
  if (!(step > 0 && step < 1)) throw OptionError(&step, "push_factor", "must lie in (0, 1)");
  // Bounded: each iteration is a nearest-point query per vertex (10^9 hung).
  if (cooling_iterations < 1 || cooling_iterations > 10000) {
    throw OptionError(&cooling_iterations, "cooling_iterations", "must lie in 1 .. 10000 (default 30)");
  }
  if (growth_iterations < 0 || growth_iterations > 100000) {
    throw OptionError(&growth_iterations, "growth_iterations", "must lie in 0 .. 100000 (default 200)");
  }
  if (threads < 0) throw OptionError(&threads, "threads", "must be at least 0");
}

double MedialSpheres::MinRadius() const {
  double r = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < radii.size(); ++i) {
    if (valid[i] && !contact[i]) r = std::min(r, radii[i]);
  }
  return std::isfinite(r) ? r : 0.0;
}

double MedialSpheres::MaxRadius() const {
  double r = 0.0;
  for (std::size_t i = 0; i < radii.size(); ++i) {
    if (valid[i] && !contact[i]) r = std::max(r, radii[i]);
  }
  return r;
}

namespace {

// A sphere inside a closed solid lies inside the solid's bounding box.
bool BallInsideBox(const Eigen::Vector3d& centre, double radius, const Aabb& box) {
  return std::isfinite(radius) && (centre.array() - radius >= box.min.array()).all() &&
         (centre.array() + radius <= box.max.array()).all();
}

}  // namespace

MedialSpheres ComputeMedialSpheres(const MeshTopology& topology, const MedialSphereOptions& options) {
  options.Check();
  const auto started = std::chrono::steady_clock::now();
  const int n = topology.VertexCount();
  MedialSpheres out;
  out.centers = topology.vertices;
  out.radii.assign(n, 0.0);
  out.valid.assign(n, 0);
  out.contact.assign(n, 0);
  const TriangleBvh bvh(topology.vertices, topology.triangles);
  const double delta = options.delta * topology.diagonal;
  const double step = options.step;
  const int cooling = options.cooling_iterations;
  const double growth_ratio = 1.0 + step / 4.0;
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  std::atomic<std::int64_t> done{0};
  std::int64_t queries = 0;
  std::int64_t escaped = 0;
  Aabb bounds;
  for (const auto& vertex : topology.vertices) bounds.Extend(vertex);

#pragma omp parallel for schedule(dynamic, 32) num_threads(threads) reduction(+ : queries, escaped)
  for (int v = 0; v < n; ++v) {
    if (CancelRequested()) continue;  // thrown after the loop (core/cancel.h)
    if (topology.referenced[v]) {
      const auto& triangles = topology.triangles;
      const TriangleBvh::Nearest other = bvh.NearestPoint(topology.vertices[v], [&](int t) {
        return triangles[t][0] == v || triangles[t][1] == v || triangles[t][2] == v;
      });
      ++queries;
      out.contact[v] = other.triangle >= 0 && other.distance_squared < delta * delta ? 1 : 0;
      const Eigen::Vector3d& normal = topology.vertex_normals[v];
      Eigen::Vector3d p = topology.vertices[v] - delta * normal;
      TriangleBvh::Nearest near = bvh.NearestPoint(p);
      ++queries;
      // p moves away from p_near by eps times the distance; where p lies on
      // the surface (no direction), it moves inward along the normal instead.
      const auto advance = [&](double eps) {
        if (near.distance_squared > 0) {
          p += eps * (p - near.point);
        } else {
          p -= delta * normal;
        }
        near = bvh.NearestPoint(p, near.triangle);
        ++queries;
      };
      double history[4] = {std::sqrt(near.distance_squared), 0, 0, 0};
      for (int g = 1; g <= options.growth_iterations; ++g) {
        advance(step);
        const double d = std::sqrt(near.distance_squared);
        history[g % 4] = d;
        if (g >= 3 && !(d > history[(g - 3) % 4] * growth_ratio)) break;
      }
      for (int k = 0; k < cooling; ++k) advance(step * (1.0 - static_cast<double>(k) / cooling));
      const double radius = std::sqrt(near.distance_squared);
      if (BallInsideBox(p, radius, bounds)) {
        out.centers[v] = p;
        out.radii[v] = radius;
        out.valid[v] = 1;
      } else {
        // The walk left D: the vertex's normal points out of the solid it
        // bounds (a vertex shared by overlapping solids of a soup, an open
        // or inverted surface), and p grew in the empty space around D
        // (radii of 1e51 were seen). No thickness is known here.
        ++escaped;
      }
    }
    const std::int64_t finished = ++done;
    if (options.progress && omp_get_thread_num() == 0 && (finished % 64 == 0 || finished == n)) {
      options.progress(finished, n);
    }
  }
  ThrowIfCancelled();
  if (options.progress) options.progress(n, n);
  out.nearest_queries = queries;
  out.escaped = escaped;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return out;
}

// ---------------------------------------------------------------- artifact

SpheresArtifact ToSpheresArtifact(const MeshTopology& topology, const MedialSpheres& spheres) {
  SpheresArtifact out;
  const int n = topology.OriginalVertexCount();
  out.centers.resize(n);
  out.radii.resize(n);
  out.normals.resize(n);
  out.valid.resize(n);
  out.contact.resize(n);
  for (int i = 0; i < n; ++i) {
    const int w = topology.welded_of_original[i];
    out.centers[i] = spheres.centers[w];
    out.radii[i] = spheres.radii[w];
    out.normals[i] = topology.vertex_normals[w];
    out.valid[i] = spheres.valid[w];
    out.contact[i] = spheres.contact[w];
  }
  return out;
}

namespace {

std::vector<double> Flatten(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> flat;
  flat.reserve(3 * points.size());
  for (const auto& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  return flat;
}

std::vector<Eigen::Vector3d> Unflatten(const Array<double>& array) {
  std::vector<Eigen::Vector3d> points(array.dims[0]);
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = Eigen::Vector3d(array.data[3 * i], array.data[3 * i + 1], array.data[3 * i + 2]);
  }
  return points;
}

}  // namespace

void WriteSpheresArtifact(const std::filesystem::path& path, const SpheresArtifact& spheres,
                          const Provenance& provenance) {
  const std::size_t n = spheres.radii.size();
  ArtifactWriter writer(path, kSpheresSchema, kSpheresSchemaVersion, provenance);
  writer.WriteDoubles("centers", Flatten(spheres.centers), {n, 3});
  writer.WriteDoubles("radii", spheres.radii, {n});
  writer.WriteDoubles("normals", Flatten(spheres.normals), {n, 3});
  writer.WriteBytes("valid", spheres.valid, {n});
  writer.WriteBytes("contact", spheres.contact, {n});
  if (!spheres.units.empty()) {
    writer.SetAttribute("centers", "units", spheres.units);
    writer.SetAttribute("radii", "units", spheres.units);
  }
  double r_min = std::numeric_limits<double>::infinity(), r_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!spheres.valid[i] || spheres.contact[i]) continue;
    r_min = std::min(r_min, spheres.radii[i]);
    r_max = std::max(r_max, spheres.radii[i]);
  }
  writer.SetAttribute("", "r_min", std::isfinite(r_min) ? r_min : 0.0);
  writer.SetAttribute("", "r_max", r_max);
  writer.SetAttribute("", "vertices", static_cast<std::int64_t>(n));
  writer.Commit();
}

SpheresArtifact ReadSpheresArtifact(const std::filesystem::path& path) {
  ArtifactReader reader(path, kSpheresSchema, kSpheresSchemaVersion);
  SpheresArtifact out;
  const Array<double> centers = reader.ReadDoubles("centers", 2);
  const Array<double> radii = reader.ReadDoubles("radii", 1);
  const std::size_t n = radii.dims[0];
  if (centers.dims[0] != n || centers.dims[1] != 3) {
    throw InputErrorAt(path.string(), "dataset 'centers' has shape [" + std::to_string(centers.dims[0]) + "," +
                                          std::to_string(centers.dims[1]) + "] (expected [" + std::to_string(n) +
                                          ",3])");
  }
  out.centers = Unflatten(centers);
  out.radii = radii.data;
  if (reader.Has("normals")) {
    const Array<double> normals = reader.ReadDoubles("normals", 2);
    if (normals.dims[0] != n || normals.dims[1] != 3) {
      throw InputErrorAt(path.string(), "dataset 'normals' does not match 'radii' in shape");
    }
    out.normals = Unflatten(normals);
  }
  if (reader.Has("valid")) {
    const Array<std::uint8_t> valid = reader.ReadBytes("valid", 1);
    if (valid.dims[0] != n) throw InputErrorAt(path.string(), "dataset 'valid' does not match 'radii' in shape");
    out.valid = valid.data;
  } else {
    out.valid.assign(n, 1);
  }
  if (reader.Has("contact")) {
    const Array<std::uint8_t> contact = reader.ReadBytes("contact", 1);
    if (contact.dims[0] != n) throw InputErrorAt(path.string(), "dataset 'contact' does not match 'radii' in shape");
    out.contact = contact.data;
  } else {
    out.contact.assign(n, 0);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!out.centers[i].allFinite()) {
      throw InputErrorAt(path.string(), "dataset 'centers' holds a non-finite value at " + std::to_string(i));
    }
    if (!out.normals.empty() && !out.normals[i].allFinite()) {
      throw InputErrorAt(path.string(), "dataset 'normals' holds a non-finite value at " + std::to_string(i));
    }
    if (!std::isfinite(out.radii[i]) || out.radii[i] < 0) {
      throw InputErrorAt(path.string(), "dataset 'radii' holds a negative or non-finite value at " + std::to_string(i));
    }
  }
  return out;
}

void WriteSpheresCsv(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& vertices,
                     const std::vector<double>& radii) {
  std::string text = "x,y,z,radius\n";
  text.reserve(80 * vertices.size() + 16);
  char line[160];
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g\n", vertices[i].x(), vertices[i].y(), vertices[i].z(),
                  radii[i]);
    text += line;
  }
  WriteTextFileAtomically(path, text);
}

}  // namespace ausbau
