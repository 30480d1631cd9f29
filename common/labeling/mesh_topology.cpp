#include "labeling/mesh_topology.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/weld.h"

namespace ausbau {
namespace {

// Fixed, deliberately irregular directions for ray-parity tests (no axis
// alignment, so rays rarely run along edges of CAD meshes).
const Eigen::Vector3d kRayDirections[3] = {
    Eigen::Vector3d(0.5773502691896258, 0.5914394147712337, 0.5632542613410031),
    Eigen::Vector3d(-0.7071067811865476, 0.3111442126341125, 0.6348234758123451),
    Eigen::Vector3d(0.1357890123456789, -0.8124038404635961, 0.5670102939401234)};

int Find(std::vector<int>& parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// The phases of BuildMeshTopology, in order; each fills its part of `topo`.

// 1-2. Weld, then drop collapsed, zero-area and repeated triangles.
void WeldAndClean(const TriangleMesh& mesh, const MeshTopologyOptions& options, double input_diagonal,
                  const Aabb& input_box, MeshTopology* topo_out) {
  MeshTopology& topo = *topo_out;
  MeshTopologyStats& stats = topo.stats;
  // Cells of the weld's grid are counted from the input's box; with no
  // tolerance they are still small, so that few vertices share one.
  const double weld_tolerance = std::max(0.0, options.weld_tolerance) * input_diagonal;
  const double weld_cell = weld_tolerance > 0 ? weld_tolerance : (input_diagonal > 0 ? input_diagonal * 1e-9 : 1.0);
  topo.welded_of_original = WeldWithinTolerance(mesh.vertices, weld_tolerance, WeldDistance::kEuclidean, input_box.min,
                                                weld_cell, &topo.vertices);
  const int n = topo.VertexCount();
  stats.welded_vertices = n;

  // Clean: drop collapsed, zero-area and repeated triangles.
  const double min_cross = 1e-13 * input_diagonal * input_diagonal;
  struct Candidate {
    std::array<int, 3> sorted;
    int index;
  };
  std::vector<Candidate> candidates;
  std::vector<std::array<int, 3>> remapped(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    std::array<int, 3> w;
    for (int k = 0; k < 3; ++k) w[k] = topo.welded_of_original[mesh.triangles[t][k]];
    remapped[t] = w;
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
      ++stats.degenerate_triangles;
      continue;
    }
    const Eigen::Vector3d cross =
        (topo.vertices[w[1]] - topo.vertices[w[0]]).cross(topo.vertices[w[2]] - topo.vertices[w[0]]);
    if (!(cross.norm() > min_cross)) {
      ++stats.degenerate_triangles;
      continue;
    }
    std::array<int, 3> sorted = w;
    std::sort(sorted.begin(), sorted.end());
    candidates.push_back({sorted, static_cast<int>(t)});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.sorted != b.sorted ? a.sorted < b.sorted : a.index < b.index;
  });
  std::vector<int> kept;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (i > 0 && candidates[i].sorted == candidates[i - 1].sorted) {
      ++stats.duplicate_triangles;
      continue;
    }
    kept.push_back(candidates[i].index);
  }
  std::sort(kept.begin(), kept.end());  // input order
  if (kept.empty()) {
    const std::string what = "the part D has no triangle of positive area";
    throw options.source.empty() ? InputError(what) : InputErrorAt(options.source, what);
  }
  const int m = static_cast<int>(kept.size());
  topo.source_triangle = kept;
  topo.triangles.resize(m);
  for (int t = 0; t < m; ++t) topo.triangles[t] = remapped[kept[t]];
}

// The edges of the triangles (topo.edges, edge_triangles and their offsets)
// and, per triangle, its three edges (slot k: tri[k] -> tri[k+1]).
std::vector<std::array<int, 3>> BuildEdges(MeshTopology* topo_out) {
  MeshTopology& topo = *topo_out;
  MeshTopologyStats& stats = topo.stats;
  const int m = static_cast<int>(topo.triangles.size());
  // (a, b, triangle, slot k of the directed edge tri[k] -> tri[k+1]).
  struct HalfEdge {
    int a, b, triangle, slot;
  };
  std::vector<HalfEdge> half(3 * static_cast<std::size_t>(m));
  for (int t = 0; t < m; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int u = topo.triangles[t][k], v = topo.triangles[t][(k + 1) % 3];
      half[3 * t + k] = {std::min(u, v), std::max(u, v), t, k};
    }
  }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.triangle < y.triangle;
  });
  std::vector<std::array<int, 3>> triangle_edges(m);
  topo.edge_triangle_offsets.push_back(0);
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    const int e = static_cast<int>(topo.edges.size());
    topo.edges.push_back({half[i].a, half[i].b});
    for (; j < half.size() && half[j].a == half[i].a && half[j].b == half[i].b; ++j) {
      topo.edge_triangles.push_back(half[j].triangle);
      triangle_edges[half[j].triangle][half[j].slot] = e;
    }
    const int count = static_cast<int>(j - i);
    if (count == 1) ++stats.boundary_edges;
    if (count > 2) ++stats.non_manifold_edges;
    topo.edge_triangle_offsets.push_back(static_cast<int>(topo.edge_triangles.size()));
    i = j;
  }
  return triangle_edges;
}

int EdgeTriangleCount(const MeshTopology& topo, int e) {
  return topo.edge_triangle_offsets[e + 1] - topo.edge_triangle_offsets[e];
}

// Whether triangle tri (as given) runs along edge e from its lower to its higher vertex.
bool RunsForward(const MeshTopology& topo, const std::array<int, 3>& tri, int e) {
  const int a = topo.edges[e][0], b = topo.edges[e][1];
  for (int k = 0; k < 3; ++k) {
    if (tri[k] == a && tri[(k + 1) % 3] == b) return true;
  }
  return false;
}

void FlipTriangle(MeshTopology* topo, int t) { std::swap(topo->triangles[t][1], topo->triangles[t][2]); }

// 3. Patches oriented consistently by breadth-first search over manifold
// edges (flipped triangles marked in *flip and flipped in topo).
std::vector<std::vector<int>> OrientPatches(const std::vector<std::array<int, 3>>& triangle_edges,
                                            const MeshTopologyOptions& options, std::vector<std::uint8_t>* flip_out,
                                            MeshTopology* topo_out) {
  MeshTopology& topo = *topo_out;
  const int m = static_cast<int>(topo.triangles.size());
  std::vector<std::uint8_t>& flip = *flip_out;
  flip.assign(m, 0);
  topo.triangle_patch.assign(m, -1);
  std::vector<std::vector<int>> patches;
  std::vector<int> queue;
  for (int seed = 0; seed < m; ++seed) {
    if (topo.triangle_patch[seed] >= 0) continue;
    if (!options.orient) {  // one patch per triangle, nothing flipped
      topo.triangle_patch[seed] = static_cast<int>(patches.size());
      patches.push_back({seed});
      continue;
    }
    const int patch = static_cast<int>(patches.size());
    patches.emplace_back();
    queue.assign(1, seed);
    topo.triangle_patch[seed] = patch;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int t = queue[head];
      patches[patch].push_back(t);
      for (int k = 0; k < 3; ++k) {
        const int e = triangle_edges[t][k];
        if (EdgeTriangleCount(topo, e) != 2) continue;
        const int* pair = &topo.edge_triangles[topo.edge_triangle_offsets[e]];
        const int u = pair[0] == t ? pair[1] : pair[0];
        if (topo.triangle_patch[u] >= 0) continue;
        const bool t_forward = RunsForward(topo, topo.triangles[t], e) != (flip[t] != 0);
        const bool u_forward = RunsForward(topo, topo.triangles[u], e);
        flip[u] = (u_forward == t_forward) ? 1 : 0;  // consistent neighbours run the edge in opposite directions
        topo.triangle_patch[u] = patch;
        queue.push_back(u);
      }
    }
  }
  for (int t = 0; t < m; ++t) {
    if (flip[t]) FlipTriangle(&topo, t);
  }
  topo.stats.patches = static_cast<int>(patches.size());

  return patches;
}

// Normals and areas of the (patch-consistent) triangles.
void ComputeTriangleGeometry(MeshTopology* topo_out) {
  MeshTopology& topo = *topo_out;
  const int m = static_cast<int>(topo.triangles.size());
  topo.triangle_normals.resize(m);
  topo.triangle_areas.resize(m);
  const auto update_geometry = [&](int t) {
    const auto& tri = topo.triangles[t];
    const Eigen::Vector3d cross =
        (topo.vertices[tri[1]] - topo.vertices[tri[0]]).cross(topo.vertices[tri[2]] - topo.vertices[tri[0]]);
    const double norm = cross.norm();
    topo.triangle_areas[t] = 0.5 * norm;
    topo.triangle_normals[t] = cross / norm;
  };
  for (int t = 0; t < m; ++t) update_geometry(t);
}

// 4. Each patch turned outward as a whole: a closed patch by its signed
// volume (and inward where it is a cavity inside the others), an open one
// by rays from sample triangles.
void OrientPatchesGlobally(const std::vector<std::vector<int>>& patches,
                           const std::vector<std::array<int, 3>>& triangle_edges, const MeshTopologyOptions& options,
                           double input_diagonal, std::vector<std::uint8_t>* flip_out, MeshTopology* topo_out) {
  MeshTopology& topo = *topo_out;
  MeshTopologyStats& stats = topo.stats;
  const int m = static_cast<int>(topo.triangles.size());
  std::vector<std::uint8_t>& flip = *flip_out;
  const TriangleBvh bvh = options.orient ? TriangleBvh(topo.vertices, topo.triangles) : TriangleBvh();
  const double t_min = 1e-9 * input_diagonal;
  const auto centroid = [&](int t) {
    const auto& tri = topo.triangles[t];
    return Eigen::Vector3d((topo.vertices[tri[0]] + topo.vertices[tri[1]] + topo.vertices[tri[2]]) / 3.0);
  };
  const auto samples_of = [&](const std::vector<int>& list) {
    std::vector<int> out;
    const int count = static_cast<int>(list.size());
    const int wanted = std::max(1, std::min(count, options.orientation_samples));
    for (int s = 0; s < wanted; ++s) out.push_back(list[static_cast<std::size_t>(s) * count / wanted]);
    return out;
  };
  for (int p = 0; p < stats.patches && options.orient; ++p) {
    const std::vector<int>& list = patches[p];
    bool closed = true;
    for (int t : list) {
      for (int k = 0; k < 3; ++k) closed = closed && EdgeTriangleCount(topo, triangle_edges[t][k]) == 2;
    }
    bool flip_patch = false;
    if (closed) {
      ++stats.closed_patches;
      const Eigen::Vector3d origin = topo.vertices[topo.triangles[list.front()][0]];
      double volume = 0.0;
      for (int t : list) {
        const auto& tri = topo.triangles[t];
        volume += (topo.vertices[tri[0]] - origin)
                      .dot((topo.vertices[tri[1]] - origin).cross(topo.vertices[tri[2]] - origin));
      }
      flip_patch = volume < 0;
      // A cavity: every sample lies inside the other surfaces.
      if (stats.patches > 1) {
        bool all_inside = true;
        for (int t : samples_of(list)) {
          int odd = 0;
          for (const auto& direction : kRayDirections) {
            odd += bvh.CountCrossings(centroid(t), direction, t_min, [&](int u) {
              return topo.triangle_patch[u] == p;
            }) % 2;
          }
          if (odd < 2) {
            all_inside = false;
            break;
          }
        }
        if (all_inside) {
          ++stats.cavity_patches;
          flip_patch = !flip_patch;
        }
      }
    } else {
      double inward = 0.0, outward = 0.0;
      for (int t : samples_of(list)) {
        const Eigen::Vector3d& normal = topo.triangle_normals[t];
        int odd = 0;
        for (const auto& direction : kRayDirections) {
          const Eigen::Vector3d ray = (normal + 0.6 * direction).normalized();
          odd += bvh.CountCrossings(centroid(t), ray, t_min, [&](int u) { return u == t; }) % 2;
        }
        (odd >= 2 ? inward : outward) += topo.triangle_areas[t];
      }
      flip_patch = inward > outward;
    }
    if (flip_patch) {
      for (int t : list) {
        FlipTriangle(&topo, t);
        flip[t] ^= 1;
        topo.triangle_normals[t] = -topo.triangle_normals[t];
      }
    }
  }
  for (int t = 0; t < m; ++t) stats.flipped_triangles += flip[t];
}

// 5. Vertex normals and areas, bounds, connected components.
void ComputeVertexData(MeshTopology* topo_out) {
  MeshTopology& topo = *topo_out;
  MeshTopologyStats& stats = topo.stats;
  const int n = topo.VertexCount();
  const int m = static_cast<int>(topo.triangles.size());
  topo.vertex_normals.assign(n, Eigen::Vector3d::Zero());
  topo.vertex_areas.assign(n, 0.0);
  topo.referenced.assign(n, 0);
  std::vector<double> largest_area(n, -1.0);
  std::vector<int> largest(n, -1);
  std::vector<double> weight_sum(n, 0.0);
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int t = 0; t < m; ++t) {
    const double area = topo.triangle_areas[t];
    for (int v : topo.triangles[t]) {
      topo.vertex_normals[v] += area * topo.triangle_normals[t];
      weight_sum[v] += area;
      topo.vertex_areas[v] += area / 3.0;
      topo.referenced[v] = 1;
      if (area > largest_area[v]) {
        largest_area[v] = area;
        largest[v] = t;
      }
    }
    const int r0 = Find(parent, topo.triangles[t][0]);
    for (int k = 1; k < 3; ++k) {
      const int rk = Find(parent, topo.triangles[t][k]);
      if (rk != r0) parent[std::max(rk, r0)] = std::min(rk, r0);
    }
  }
  topo.component.assign(n, -1);
  std::vector<int> component_of_root(n, -1);
  for (int v = 0; v < n; ++v) {
    if (!topo.referenced[v]) {
      ++stats.unreferenced_vertices;
      continue;
    }
    const double norm = topo.vertex_normals[v].norm();
    if (norm > 1e-12 * weight_sum[v]) {
      topo.vertex_normals[v] /= norm;
    } else {
      topo.vertex_normals[v] = topo.triangle_normals[largest[v]];
    }
    topo.bounds.Extend(topo.vertices[v]);
    const int root = Find(parent, v);
    if (component_of_root[root] < 0) component_of_root[root] = stats.components++;
    topo.component[v] = component_of_root[root];
  }
}

}  // namespace

// ---------------------------------------------------------------- topology

MeshTopology BuildMeshTopology(const TriangleMesh& mesh, const MeshTopologyOptions& options) {
  MeshTopology topo;
  topo.stats.input_vertices = static_cast<int>(mesh.vertices.size());
  topo.stats.input_triangles = static_cast<int>(mesh.triangles.size());
  const Aabb input_box = mesh.Bounds();
  const double input_diagonal = input_box.Diagonal();
  WeldAndClean(mesh, options, input_diagonal, input_box, &topo);
  const std::vector<std::array<int, 3>> triangle_edges = BuildEdges(&topo);
  std::vector<std::uint8_t> flip;
  const std::vector<std::vector<int>> patches = OrientPatches(triangle_edges, options, &flip, &topo);
  ComputeTriangleGeometry(&topo);
  OrientPatchesGlobally(patches, triangle_edges, options, input_diagonal, &flip, &topo);
  ComputeVertexData(&topo);
  topo.diagonal = topo.bounds.Diagonal();
  return topo;
}

// ---------------------------------------------------------------- grid solids

TriangleMesh MakeGridSolidMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                               const std::vector<double>& zs, const std::function<bool(int, int, int)>& filled) {
  const int nx = static_cast<int>(xs.size()) - 1, ny = static_cast<int>(ys.size()) - 1,
            nz = static_cast<int>(zs.size()) - 1;
  TriangleMesh mesh;
  if (nx < 1 || ny < 1 || nz < 1) return mesh;
  const auto solid = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && filled(i, j, k);
  };
  std::unordered_map<std::int64_t, int> point_index;
  const auto point = [&](int i, int j, int k) {
    const std::int64_t key = (static_cast<std::int64_t>(i) * (ny + 1) + j) * (nz + 1) + k;
    const auto it = point_index.find(key);
    if (it != point_index.end()) return it->second;
    const int index = static_cast<int>(mesh.vertices.size());
    mesh.vertices.emplace_back(xs[i], ys[j], zs[k]);
    point_index.emplace(key, index);
    return index;
  };
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < nz; ++k) {
        if (!solid(i, j, k)) continue;
        const int cell[3] = {i, j, k};
        for (int axis = 0; axis < 3; ++axis) {
          for (int side = 0; side < 2; ++side) {
            int neighbour[3] = {i, j, k};
            neighbour[axis] += side == 0 ? -1 : 1;
            if (solid(neighbour[0], neighbour[1], neighbour[2])) continue;
            // Quad in the plane axis = cell[axis] + side, spanned by the two
            // following axes (u, v) in cyclic order: e_u x e_v = e_axis.
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            int corner[4];
            const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
            for (int c = 0; c < 4; ++c) {
              int g[3];
              g[axis] = cell[axis] + side;
              g[u] = cell[u] + du[c];
              g[v] = cell[v] + dv[c];
              corner[c] = point(g[0], g[1], g[2]);
            }
            if (side == 1) {
              mesh.triangles.push_back({corner[0], corner[1], corner[2]});
              mesh.triangles.push_back({corner[0], corner[2], corner[3]});
            } else {
              mesh.triangles.push_back({corner[0], corner[2], corner[1]});
              mesh.triangles.push_back({corner[0], corner[3], corner[2]});
            }
          }
        }
      }
    }
  }
  return mesh;
}

// ---------------------------------------------------------------- PLY

std::array<std::uint8_t, 3> RampColor(ColorRamp ramp, double t) {
  if (!(t >= 0)) t = 0;  // also NaN
  if (t > 1) t = 1;
  const auto mix = [](const double* a, const double* b, double s) {
    std::array<std::uint8_t, 3> out;
    for (int k = 0; k < 3; ++k) out[k] = static_cast<std::uint8_t>(std::lround(a[k] + s * (b[k] - a[k])));
    return out;
  };
  if (ramp == ColorRamp::kLargeToSmall) {
    static const double small[3] = {255, 215, 0}, large[3] = {0, 70, 255};
    return mix(small, large, t);
  }
  static const double stops[5][3] = {{0, 0, 255}, {0, 200, 255}, {0, 200, 0}, {255, 220, 0}, {230, 0, 0}};
  const double x = t * 4.0;
  const int i = std::min(3, static_cast<int>(x));
  return mix(stops[i], stops[i + 1], x - i);
}

void WriteColoredPly(const std::filesystem::path& path, const TriangleMesh& mesh, const std::vector<double>& values,
                     const std::string& property, ColorRamp ramp, double lo, double hi, const std::string& comment) {
  if (values.size() != mesh.vertices.size()) {
    throw std::runtime_error(path.string() + ": " + std::to_string(values.size()) + " values for " +
                             std::to_string(mesh.vertices.size()) + " vertices");
  }
  std::string out = "ply\nformat binary_little_endian 1.0\n";
  if (!comment.empty()) out += "comment " + comment + "\n";
  out += "element vertex " + std::to_string(mesh.vertices.size()) +
         "\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float " +
         property + "\nelement face " + std::to_string(mesh.triangles.size()) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
  const auto put32 = [&out](std::uint32_t bits) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((bits >> (8 * k)) & 0xFF));
  };
  const auto put_float = [&](double value) {
    const float f = static_cast<float>(value);
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put32(bits);
  };
  const double range = hi > lo ? hi - lo : 1.0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) put_float(mesh.vertices[i][k]);
    const auto rgb = RampColor(ramp, (values[i] - lo) / range);
    for (int k = 0; k < 3; ++k) out.push_back(static_cast<char>(rgb[k]));
    put_float(values[i]);
  }
  for (const auto& tri : mesh.triangles) {
    out.push_back(3);
    for (int k = 0; k < 3; ++k) put32(static_cast<std::uint32_t>(tri[k]));
  }
  WriteTextFileAtomically(path, out);
}

std::vector<std::uint8_t> ExposedVertices(const MeshTopology& topo) {
  const TriangleBvh bvh(topo.vertices, topo.triangles);
  std::vector<int> component(topo.triangles.size());
  for (std::size_t t = 0; t < component.size(); ++t) component[t] = topo.component[topo.triangles[t][0]];
  const Eigen::Vector3d directions[3] = {Eigen::Vector3d(0.577, 0.591, 0.563).normalized(),
                                         Eigen::Vector3d(-0.707, 0.311, 0.634).normalized(),
                                         Eigen::Vector3d(0.135, -0.812, 0.567).normalized()};
  std::vector<std::uint8_t> exposed(topo.OriginalVertexCount(), 1);
  for (int i = 0; i < topo.OriginalVertexCount(); ++i) {
    const int w = topo.welded_of_original[i];
    const int own = topo.component[w];
    const auto others = [&](int t) { return component[t] == own; };
    const auto near = bvh.NearestPoint(topo.vertices[w], others);
    if (near.triangle >= 0 && near.distance_squared < 1e-4 * topo.diagonal * topo.diagonal * 1e-4) {
      exposed[i] = 0;
      continue;
    }
    int odd = 0;
    for (const auto& direction : directions) odd += bvh.CountCrossings(topo.vertices[w], direction, 0, others) % 2;
    if (odd >= 2) exposed[i] = 0;
  }
  return exposed;
}

}  // namespace ausbau
