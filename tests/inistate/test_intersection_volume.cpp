// InIState: clip scenes and their ground truth, voxelization (generalized
// winding number), IV / MLIV / Labeled-MLIV, and ausbau-voxelize.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

#include "artifact/artifact.h"
#include "collision/fcl_checker.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/random.h"
#include "fixtures/clip_scenes.h"
#include "geometry/primitives.h"
#include "geometry/principal_axes.h"
#include "inistate/intersection_volume.h"
#include "inistate/voxel_grid.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

Aabb Box(const Vec3& min, const Vec3& max) {
  Aabb box;
  box.Extend(min);
  box.Extend(max);
  return box;
}

Pose Translation(const Vec3& t) {
  Pose p;
  p.t = t;
  return p;
}

// ------------------------------------------------------------ voxelization

TEST(Voxelize, CubeVolume) {
  const double side = 10.0, h = 0.5;
  const TriangleMesh cube = MakeBox({0.13, 0.29, -0.07}, {0.13 + side, 0.29 + side, -0.07 + side});
  VoxelizeStats stats;
  const VoxelGrid grid = VoxelizeMesh(cube, GridAround(cube.Bounds(), h), {}, &stats);
  const double n = side / h;  // 20 voxels along an edge
  const std::int64_t occupied = grid.CountOccupied();
  // Surface voxels reach at most one voxel layer beyond each face.
  EXPECT_GE(occupied, static_cast<std::int64_t>(n * n * n));
  EXPECT_LE(occupied, static_cast<std::int64_t>((n + 2) * (n + 2) * (n + 2)));
  EXPECT_GE(grid.Count(kVoxelInside), static_cast<std::int64_t>((n - 2) * (n - 2) * (n - 2)));
  EXPECT_EQ(stats.open_triangles, 0);
  EXPECT_EQ(stats.closed_triangles, 12);
  EXPECT_EQ(stats.regions, 2);  // outside and inside of the surface shell
  // The centre is inside, a corner of the grid outside.
  const Vec3 c = cube.Bounds().Center();
  const Eigen::Vector3i cell = ((c - grid.geometry.origin) / h).array().floor().cast<int>();
  EXPECT_EQ(grid.cells[grid.geometry.Index(cell.x(), cell.y(), cell.z())], kVoxelInside);
  EXPECT_EQ(grid.cells[0], kVoxelEmpty);
}

// Cancelled (core/cancel.h): the parallel passes skip their work and the
// voxelization throws after them, and reports progress up to then.
TEST(Voxelize, CancelStopsTheParallelPasses) {
  const TriangleMesh cube = MakeBox({0, 0, 0}, {1, 1, 1});
  VoxelizeOptions options;
  std::int64_t reports = 0;
  options.progress = [&reports](std::int64_t, std::int64_t) { ++reports; };
  EXPECT_NO_THROW(VoxelizeMesh(cube, GridAround(cube.Bounds(), 0.05), options));
  EXPECT_GT(reports, 0);
  RequestCancel();
  EXPECT_THROW(VoxelizeMesh(cube, GridAround(cube.Bounds(), 0.05), options), Cancelled);
  ResetCancel();
}

TEST(Voxelize, InvertedCubeIsStillFilled) {
  TriangleMesh cube = MakeBox({0, 0, 0}, {4, 4, 4});
  for (auto& t : cube.triangles) std::swap(t[1], t[2]);  // normals inwards
  const VoxelGrid grid = VoxelizeMesh(cube, GridAround(cube.Bounds(), 0.5));
  EXPECT_GE(grid.Count(kVoxelInside), 6 * 6 * 6);
}

TEST(Voxelize, PlateWithHoleLeavesTheHoleEmpty) {
  const double h = 0.25;
  const TriangleMesh plate = MakePlateWithHole(5.0, 2.0, -0.5, 0.5);
  const VoxelGrid grid = VoxelizeMesh(plate, GridAround(plate.Bounds(), h));
  const VoxelGridGeometry& g = grid.geometry;
  int hole_checked = 0, material_checked = 0;
  for (int k = 0; k < g.dims[2]; ++k) {
    for (int j = 0; j < g.dims[1]; ++j) {
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 p = g.Center(i, j, k);
        const std::uint8_t s = grid.cells[g.Index(i, j, k)];
        if (std::abs(p.x()) < 2.0 - h && std::abs(p.y()) < 2.0 - h) {
          EXPECT_EQ(s, kVoxelEmpty) << "in the hole at " << p.transpose();
          ++hole_checked;
        }
        // (The plate is four boxes: their shared faces at |y| = 2 are surface too.)
        const double r = std::max(std::abs(p.x()), std::abs(p.y()));
        if (r > 2.0 + h && r < 5.0 - h && std::abs(p.z()) < 0.5 - h && std::abs(std::abs(p.y()) - 2.0) > h) {
          EXPECT_EQ(s, kVoxelInside) << "in the plate at " << p.transpose();
          ++material_checked;
        }
      }
    }
  }
  EXPECT_GT(hole_checked, 100);
  EXPECT_GT(material_checked, 100);
}

TEST(Voxelize, BoxWithAMissingFaceIsFilledUpToTheOpening) {
  // Documented classification (voxel_grid.h): the winding number is >= 0.5
  // on the box's side of the missing face's plane, so the box is filled as if
  // it were closed; beyond the opening nothing is inside.
  const double h = 0.5;
  const TriangleMesh closed = MakeBox({0, 0, 0}, {8, 8, 8});
  TriangleMesh open = closed;
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);  // the z = max face
  const VoxelGridGeometry g = GridAround(Box({0, 0, 0}, {8, 8, 12}), h);
  VoxelizeStats stats;
  const VoxelGrid a = VoxelizeMesh(closed, g), b = VoxelizeMesh(open, g, {}, &stats);
  EXPECT_EQ(stats.open_triangles, 10);
  EXPECT_EQ(stats.closed_triangles, 0);
  std::int64_t differ = 0;
  for (int k = 0; k < g.dims[2]; ++k) {
    for (int j = 0; j < g.dims[1]; ++j) {
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vec3 p = g.Center(i, j, k);
        const std::uint8_t sa = a.cells[g.Index(i, j, k)], sb = b.cells[g.Index(i, j, k)];
        if (sa != sb) {
          ++differ;
          EXPECT_LE(std::abs(p.z() - 8), h) << "away from the missing face at " << p.transpose();
        }
        if (p.z() > 8 + h) {
          EXPECT_EQ(sb, kVoxelEmpty) << "beyond the opening at " << p.transpose();
        }
      }
    }
  }
  // Only the voxels the missing face touched may differ (two layers where it
  // lies on a voxel boundary).
  EXPECT_LE(differ, 2 * 18 * 18);
  EXPECT_GE(b.Count(kVoxelInside), 14 * 14 * 14);
}

TEST(Voxelize, HierarchicalWindingNumberMatchesExact) {
  TriangleMesh mesh = MakePlateWithHole(5.0, 2.0, -0.5, 0.5);
  mesh.triangles.resize(mesh.triangles.size() - 3);  // open it up
  const WindingBvh bvh(mesh);
  Random random(3);
  for (int n = 0; n < 500; ++n) {
    const Vec3 p(random.Uniform(-7, 7), random.Uniform(-7, 7), random.Uniform(-2, 2));
    EXPECT_NEAR(bvh.WindingNumber(p), bvh.WindingNumberExact(p), 0.02) << p.transpose();
  }
}

TEST(Voxelize, ErosionShrinksACube) {
  const TriangleMesh cube = MakeBox({0, 0, 0}, {10, 10, 10});
  const VoxelGrid grid = VoxelizeMesh(cube, GridAround(cube.Bounds(), 0.5));
  const VoxelGrid eroded = ErodeVoxels(grid, 1.0);  // two voxels
  const std::int64_t before = grid.CountOccupied(), after = eroded.CountOccupied();
  const double side_before = std::cbrt(static_cast<double>(before));
  EXPECT_NEAR(std::cbrt(static_cast<double>(after)), side_before - 4, 0.5);
}

TEST(Voxelize, MemoryGuard) {
  const VoxelGridGeometry g = GridAround(Box({0, 0, 0}, {100, 100, 100}), 0.01);
  EXPECT_THROW(CheckVoxelMemory(g, std::int64_t{2} << 30, "S's voxel grid"), InputError);
  EXPECT_NO_THROW(CheckVoxelMemory(GridAround(Box({0, 0, 0}, {1, 1, 1}), 0.1), std::int64_t{2} << 30, "x"));
  EXPECT_NEAR(AutomaticVoxelSize(Box({0, 0, 0}, {100, 50, 20}), 1000000), std::cbrt(0.1), 1e-12);
}

// ------------------------------------------------------------ IV and MLIV

// S: two blocks in a 20^3 grid of unit voxels. D: a 16 x 16 x 8 slab covering
// both at the identity pose (grids aligned, reference point at the origin).
struct HandBuilt {
  VoxelGrid s, d;
  HandBuilt() {
    s.geometry.dims = {20, 20, 20};
    s.cells.assign(s.geometry.Count(), kVoxelEmpty);
    d.geometry.dims = {16, 16, 8};
    d.cells.assign(d.geometry.Count(), kVoxelInside);
    Fill(2, 5, 2, 5, 2, 5);      // block A: 27 voxels
    Fill(10, 14, 10, 14, 2, 5);  // block B: 48 voxels
  }
  void Fill(int i0, int i1, int j0, int j1, int k0, int k1) {
    for (int k = k0; k < k1; ++k) {
      for (int j = j0; j < j1; ++j) {
        for (int i = i0; i < i1; ++i) s.cells[s.geometry.Index(i, j, k)] = kVoxelSurface;
      }
    }
  }
  // colorValue 0.1 over block B, 1 elsewhere.
  std::vector<float> Colors() const {
    std::vector<float> c(d.geometry.Count(), 1.0f);
    for (int k = 0; k < 8; ++k) {
      for (int j = 10; j < 14; ++j) {
        for (int i = 10; i < 14; ++i) c[d.geometry.Index(i, j, k)] = 0.1f;
      }
    }
    return c;
  }
};

TEST(IntersectionVolume, TwoDisjointOverlapsGiveTheLargerOne) {
  HandBuilt hb;
  IntersectionVolume volume(hb.s, hb.d, Vec3::Zero());
  VolumeQuery q;
  q.record_cells = true;
  EXPECT_DOUBLE_EQ(volume.Iv(Pose(), &q), 75.0);
  EXPECT_EQ(q.voxels, 75);
  EXPECT_DOUBLE_EQ(volume.Mliv(Pose(), &q), 48.0);
  EXPECT_EQ(q.components, 2);
  ASSERT_EQ(q.cells.size(), 48u);
  for (const auto& c : q.cells) EXPECT_GE(c.x(), 10);  // block B
  // Without labels Labeled-MLIV is MLIV.
  EXPECT_DOUBLE_EQ(volume.LabeledMliv(Pose()), 48.0);
  // Half a voxel sideways still lands in the same S voxels; 30 voxels away, nothing.
  EXPECT_DOUBLE_EQ(volume.Mliv(Translation({0.4, 0.4, 0.0})), 48.0);
  EXPECT_DOUBLE_EQ(volume.Iv(Translation({30, 0, 0})), 0.0);
  // Shifted by 3 voxels in +x, block A meets D's voxels i = -1..1: 2 x 3 x 3.
  EXPECT_DOUBLE_EQ(volume.Iv(Translation({3, 0, 0})), 18.0 + 48.0);
}

TEST(IntersectionVolume, WeightsCanMakeAnotherComponentTheMaximum) {
  HandBuilt hb;
  IntersectionVolume volume(hb.s, hb.d, Vec3::Zero(), hb.Colors());
  VolumeQuery q;
  q.record_cells = true;
  EXPECT_DOUBLE_EQ(volume.Mliv(Pose()), 48.0);  // B is the largest...
  EXPECT_NEAR(volume.LabeledMliv(Pose(), std::numeric_limits<double>::infinity(), &q), 27.0, 1e-4);  // ...A weighs most
  EXPECT_FALSE(q.early_out);
  ASSERT_EQ(q.cells.size(), 27u);
  for (const auto& c : q.cells) EXPECT_LT(c.x(), 5);  // block A
  EXPECT_FLOAT_EQ(volume.color_value(11, 11, 3), 0.1f);
  // The same voxels reweighted: unit colours give the MLIV again; one voxel
  // of block B at +infinity makes B's component weigh more than any tau.
  IntersectionVolume plain = volume.Reweighted(std::vector<float>(hb.Colors().size(), 1.0f));
  EXPECT_DOUBLE_EQ(plain.LabeledMliv(Pose()), 48.0);
  std::vector<float> guarded = hb.Colors();
  guarded[hb.d.geometry.Index(11, 11, 3)] = std::numeric_limits<float>::infinity();
  IntersectionVolume refusing = volume.Reweighted(guarded);
  EXPECT_EQ(refusing.LabeledMliv(Pose()), std::numeric_limits<double>::infinity());
  EXPECT_GT(refusing.LabeledMliv(Pose(), 1e12), 1e12);
  EXPECT_NEAR(volume.LabeledMliv(Pose()), 27.0, 1e-4);  // the original keeps its weights
  EXPECT_THROW(volume.Reweighted({1.0f}), InputError);
}

TEST(IntersectionVolume, EarlyOutStopsAtTau) {
  HandBuilt hb;
  IntersectionVolume volume(hb.s, hb.d, Vec3::Zero(), hb.Colors());
  VolumeQuery full, early;
  volume.LabeledMliv(Pose(), std::numeric_limits<double>::infinity(), &full);
  const double value = volume.LabeledMliv(Pose(), 10.0, &early);
  EXPECT_TRUE(early.early_out);
  EXPECT_GT(value, 10.0);
  EXPECT_LT(value, 27.0);        // stopped inside the first component
  EXPECT_EQ(full.visited, 75);   // every intersecting voxel
  EXPECT_LT(early.visited, 27);  // the early out visited part of one component
  EXPECT_LT(early.tested, full.tested);
  // A tau above every component: no early out, the full answer.
  VolumeQuery none;
  EXPECT_NEAR(volume.LabeledMliv(Pose(), 30.0, &none), 27.0, 1e-4);
  EXPECT_FALSE(none.early_out);
}

TEST(IntersectionVolume, ValidityThreshold) {
  HandBuilt hb;
  const IntersectionVolume volume(hb.s, hb.d, Vec3::Zero(), hb.Colors());
  const LabeledMlivValidity strict(volume, 20.0), loose(volume, 30.0);
  EXPECT_FALSE(strict.IsValid(Pose()));
  EXPECT_TRUE(loose.IsValid(Pose()));
  EXPECT_TRUE(strict.IsValid(Translation({30, 0, 0})));
}

// Brute force on the full grids: IV and MLIV by definition.
std::pair<std::int64_t, std::int64_t> BruteForce(const VoxelGrid& s, const VoxelGrid& d, const Vec3& ref,
                                                 const Pose& pose) {
  const VoxelGridGeometry& gd = d.geometry;
  std::vector<char> hit(gd.Count(), 0);
  std::int64_t iv = 0;
  for (int k = 0; k < gd.dims[2]; ++k) {
    for (int j = 0; j < gd.dims[1]; ++j) {
      for (int i = 0; i < gd.dims[0]; ++i) {
        if (d.cells[gd.Index(i, j, k)] == kVoxelEmpty) continue;
        const Vec3 w = pose.q * (gd.Center(i, j, k) - ref) + pose.t;
        const Vec3 c = (s.geometry.axes.transpose() * (w - s.geometry.origin) / s.geometry.spacing).array().floor();
        if (s.Occupied(static_cast<int>(c.x()), static_cast<int>(c.y()), static_cast<int>(c.z()))) {
          hit[gd.Index(i, j, k)] = 1;
          ++iv;
        }
      }
    }
  }
  std::int64_t mliv = 0;
  std::vector<std::int64_t> queue;
  for (std::int64_t v = 0; v < gd.Count(); ++v) {
    if (hit[v] != 1) continue;
    hit[v] = 2;
    queue.assign(1, v);
    for (size_t head = 0; head < queue.size(); ++head) {
      const std::int64_t u = queue[head];
      const int i = u % gd.dims[0], j = (u / gd.dims[0]) % gd.dims[1], k = u / (gd.dims[0] * gd.dims[1]);
      const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k}, {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
      for (const auto& n : nb) {
        if (!gd.Contains(n[0], n[1], n[2])) continue;
        const std::int64_t w = gd.Index(n[0], n[1], n[2]);
        if (hit[w] == 1) {
          hit[w] = 2;
          queue.push_back(w);
        }
      }
    }
    mliv = std::max<std::int64_t>(mliv, queue.size());
  }
  return {iv, mliv};
}

// ------------------------------------------------------------ clip scenes

struct ClipSceneData {
  Scene scene;
  ClipGroundTruth truth;
  SceneVoxels voxels;
};

const ClipSceneData& ClipScene(const std::string& family, std::int64_t triangles = 4000) {
  static std::map<std::string, ClipSceneData> cache;
  const std::string key = family + "/" + std::to_string(triangles);
  auto it = cache.find(key);
  if (it == cache.end()) {
    const auto dir = testing::MakeTempDir(family);
    ClipSceneOptions options;
    options.seed = 7;
    options.triangles = triangles;
    const ClipSceneFiles files = GenerateClipScene(family, options, dir);
    ClipSceneData data;
    data.scene = LoadScene(files.scene_yaml);
    data.truth = LoadClipGroundTruth(files.ground_truth_yaml);
    data.voxels = VoxelizeScene(data.scene, VoxelizeOptions{});
    it = cache.emplace(key, std::move(data)).first;
  }
  return it->second;
}

TriangleMesh SubMesh(const TriangleMesh& mesh, const std::vector<bool>& keep, bool value, const Vec3& shift) {
  TriangleMesh out;
  for (const Vec3& v : mesh.vertices) out.vertices.push_back(v - shift);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (keep[t] == value) out.triangles.push_back(mesh.triangles[t]);
  }
  return out;
}

class ClipFamily : public ::testing::TestWithParam<std::string> {};

TEST_P(ClipFamily, GroundTruthIsConsistent) {
  const ClipSceneData& data = ClipScene(GetParam());
  const Scene& scene = data.scene;
  const ClipGroundTruth& truth = data.truth;
  ASSERT_EQ(truth.dynamic_triangles, static_cast<std::int64_t>(scene.dynamic_mesh.triangles.size()));
  ASSERT_EQ(truth.dynamic_vertices, static_cast<std::int64_t>(scene.dynamic_mesh.vertices.size()));
  EXPECT_EQ(truth.static_triangles, static_cast<std::int64_t>(scene.static_mesh.triangles.size()));
  EXPECT_FALSE(scene.goal.has_value());
  EXPECT_FALSE(scene.bounds.has_value());
  EXPECT_TRUE(scene.dynamic_origin_given);
  EXPECT_TRUE(scene.dynamic_origin.isApprox(truth.dynamic_origin));
  EXPECT_TRUE(scene.start.t.isApprox(truth.path.front().t));

  // Parts partition D's triangles; each part's vertices are exactly the
  // vertices of its triangles.
  std::vector<int> owner(truth.dynamic_triangles, -1);
  for (size_t p = 0; p < truth.parts.size(); ++p) {
    std::set<int> from_triangles, listed;
    for (const IndexRange& r : truth.parts[p].triangles) {
      for (std::int64_t t = r.begin; t < r.end; ++t) {
        EXPECT_EQ(owner[t], -1);
        owner[t] = static_cast<int>(p);
        for (int v : scene.dynamic_mesh.triangles[t]) from_triangles.insert(v);
      }
    }
    for (const IndexRange& r : truth.parts[p].vertices) {
      for (std::int64_t v = r.begin; v < r.end; ++v) listed.insert(static_cast<int>(v));
    }
    EXPECT_EQ(from_triangles, listed) << truth.parts[p].name;
  }
  for (int o : owner) ASSERT_GE(o, 0);

  // Collision (FCL, scene convention: D relative to dynamic_origin). At the
  // start D collides, only through clip geometry (ds4: also the rails'
  // friction fit); every clip overlaps.
  const std::vector<bool> clip_mask = truth.ClipTriangleMask();
  const Vec3 origin = scene.dynamic_origin;
  TriangleMesh shifted = scene.dynamic_mesh;
  for (Vec3& v : shifted.vertices) v -= origin;
  const FclCollisionChecker all(shifted, scene.static_mesh);
  const FclCollisionChecker rigid(SubMesh(scene.dynamic_mesh, clip_mask, false, origin), scene.static_mesh);
  EXPECT_TRUE(all.InCollision(scene.start));
  EXPECT_EQ(rigid.InCollision(scene.start), truth.friction);
  int clips = 0;
  for (const ClipScenePart& part : truth.parts) {
    if (part.kind != "clip") continue;
    ++clips;
    std::vector<bool> mine(truth.dynamic_triangles, false);
    for (const IndexRange& r : part.triangles) {
      for (std::int64_t t = r.begin; t < r.end; ++t) mine[t] = true;
    }
    const FclCollisionChecker clip(SubMesh(scene.dynamic_mesh, mine, true, origin), scene.static_mesh);
    EXPECT_TRUE(clip.InCollision(scene.start)) << part.name;
    EXPECT_FALSE(part.overlap_box.Empty());
  }
  EXPECT_GT(clips, 0);

  // Along the path: rigid parts never hit S (ds4: only while sliding out of
  // the friction fit, the first segment); from the clear waypoint on nothing does.
  const auto& path = truth.path;
  for (size_t s = 0; s + 1 < path.size(); ++s) {
    const double length = (path[s + 1].t - path[s].t).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(length / 0.05)));
    for (int n = 0; n <= steps; ++n) {
      const Pose p = Interpolate(path[s], path[s + 1], static_cast<double>(n) / steps);
      if (!(truth.friction && s == 0)) {
        ASSERT_FALSE(rigid.InCollision(p)) << "segment " << s << " step " << n;
      }
      if (static_cast<int>(s) >= truth.clear_waypoint) {
        ASSERT_FALSE(all.InCollision(p)) << "segment " << s;
      }
    }
  }
  EXPECT_FALSE(all.InCollision(path[truth.clear_waypoint]));
  // The last pose is in the disassembly goal region: D's AABB above S's.
  Aabb d_box;
  for (const Vec3& v : shifted.vertices) d_box.Extend(path.back().Apply(v));
  EXPECT_TRUE(d_box.SeparatedFrom(scene.static_mesh.Bounds()));
}

TEST_P(ClipFamily, MlivAtTheBarbsAndZeroOnceClear) {
  const ClipSceneData& data = ClipScene(GetParam());
  const ClipGroundTruth& truth = data.truth;
  const double h = data.voxels.dynamic_grid.geometry.spacing;
  const std::vector<float> colors =
      ColorValues(data.voxels.dynamic_grid, data.scene.dynamic_mesh, truth.VertexDeformability());
  // Scene-convention poses: the reference point is the dynamic origin.
  IntersectionVolume volume(data.voxels.static_grid, data.voxels.dynamic_grid, data.scene.dynamic_origin, colors);
  const Pose start = truth.path.front();

  VolumeQuery iv_query, mliv_query;
  iv_query.record_cells = mliv_query.record_cells = true;
  const double iv = volume.Iv(start, &iv_query), mliv = volume.Mliv(start, &mliv_query);
  const double labeled = volume.LabeledMliv(start);
  EXPECT_GT(mliv, 0);
  EXPECT_GE(iv, mliv);
  EXPECT_GE(mliv, labeled);
  // Every intersecting voxel is clip geometry (the nearest surface of D to
  // its centre is a clip triangle: a barb, or the tongue beside the hole's
  // rim), or, for ds4, lies at a rail's friction fit (within 2 voxels of its
  // overlap box). At the start pose D's mesh coordinates are world
  // coordinates.
  const VoxelGridGeometry& gd = data.voxels.dynamic_grid.geometry;
  const WindingBvh surface(data.scene.dynamic_mesh);
  const std::vector<bool> clip_mask = truth.ClipTriangleMask();
  auto at_clip_or_fit = [&](const Eigen::Vector3i& c, bool clips_only) {
    const Vec3 p = gd.Center(c.x(), c.y(), c.z());
    if (clip_mask[surface.ClosestPoint(p).triangle]) return true;
    for (const ClipScenePart& part : truth.parts) {
      if (part.overlap_box.Empty() || (clips_only && part.kind != "clip")) continue;
      Aabb grown = part.overlap_box;
      grown.min -= Vec3::Constant(2 * h);
      grown.max += Vec3::Constant(2 * h);
      if (grown.Contains(p)) return true;
    }
    return false;
  };
  for (const auto& c : iv_query.cells) {
    ASSERT_TRUE(at_clip_or_fit(c, false)) << gd.Center(c.x(), c.y(), c.z()).transpose();
  }
  if (!truth.friction) {
    for (const auto& c : mliv_query.cells) ASSERT_TRUE(at_clip_or_fit(c, true));
  }
  // Each clip's barb overlaps: some intersecting voxel lies in its overlap box.
  for (const ClipScenePart& part : truth.parts) {
    if (part.kind != "clip") continue;
    Aabb grown = part.overlap_box;
    grown.min -= Vec3::Constant(h);
    grown.max += Vec3::Constant(h);
    EXPECT_TRUE(std::any_of(iv_query.cells.begin(), iv_query.cells.end(), [&](const Eigen::Vector3i& c) {
      return grown.Contains(gd.Center(c.x(), c.y(), c.z()));
    })) << part.name;
  }
  // Thin clips are deformable: their components weigh (almost) nothing.
  if (GetParam() == "clips-ds1" || GetParam() == "clips-ds2" || GetParam() == "clips-ds3") {
    EXPECT_LT(labeled, 0.1 * mliv);
  }

  // After the first motion that pulls the clips through, nothing intersects.
  EXPECT_DOUBLE_EQ(volume.Iv(truth.path[truth.clear_waypoint]), 0.0);
  EXPECT_DOUBLE_EQ(volume.Iv(truth.path.back()), 0.0);
  // Before it, the barbs are still in the plate.
  if (truth.clear_waypoint > 1) {
    EXPECT_GT(volume.Mliv(truth.path[1]), 0.0);
  }

  // IV >= MLIV >= Labeled-MLIV along the path, and the fast query equals the
  // brute-force definition.
  Random random(11);
  for (int n = 0; n < 12; ++n) {
    const int s = static_cast<int>(random.Index(truth.path.size() - 1));
    Pose p = Interpolate(truth.path[s], truth.path[s + 1], random.Uniform01());
    if (n % 2 == 1) p.q = Eigen::Quaterniond(Eigen::AngleAxisd(random.Uniform(-0.05, 0.05), Vec3::UnitY()));
    const double a = volume.Iv(p), b = volume.Mliv(p), c = volume.LabeledMliv(p);
    EXPECT_GE(a, b);
    EXPECT_GE(b, c - 1e-9);
    if (n < 4) {
      const auto [bf_iv, bf_mliv] =
          BruteForce(data.voxels.static_grid, data.voxels.dynamic_grid, data.scene.dynamic_origin, p);
      EXPECT_DOUBLE_EQ(a, bf_iv * volume.voxel_volume());
      EXPECT_DOUBLE_EQ(b, bf_mliv * volume.voxel_volume());
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Families, ClipFamily,
                         ::testing::Values("clips-ds1", "clips-ds2", "clips-ds3", "clips-ds4", "clips-ds5"));

TEST(ClipScenes, FamilyCharacteristics) {
  const ClipGroundTruth& ds1 = ClipScene("clips-ds1").truth;
  const ClipGroundTruth& ds2 = ClipScene("clips-ds2").truth;
  const ClipGroundTruth& ds3 = ClipScene("clips-ds3").truth;
  const ClipGroundTruth& ds4 = ClipScene("clips-ds4").truth;
  const ClipGroundTruth& ds5 = ClipScene("clips-ds5").truth;
  auto count = [](const ClipGroundTruth& t, const std::string& kind) {
    return std::count_if(t.parts.begin(), t.parts.end(), [&](const ClipScenePart& p) { return p.kind == kind; });
  };
  EXPECT_EQ(count(ds1, "clip"), 8);
  EXPECT_EQ(count(ds1, "rail"), 1);
  EXPECT_EQ(count(ds2, "clip"), 3);
  EXPECT_EQ(count(ds2, "rail"), 1);
  EXPECT_EQ(count(ds3, "clip"), 6);
  EXPECT_EQ(count(ds3, "rail"), 2);
  EXPECT_EQ(count(ds4, "rail"), 2);
  EXPECT_EQ(count(ds5, "rail"), 0);
  // ds1: the clips' overlap exceeds the rail's; ds2: it does not.
  EXPECT_GT(ds1.clip_pull_overlap, ds1.rail_block_overlap);
  EXPECT_LT(ds2.clip_pull_overlap, ds2.rail_block_overlap);
  // ds3: every clip is bigger than every rail.
  double smallest_clip = 1e300, largest_rail = 0;
  for (const auto& p : ds3.parts) {
    if (p.kind == "clip") smallest_clip = std::min(smallest_clip, p.volume);
    if (p.kind == "rail") largest_rail = std::max(largest_rail, p.volume);
  }
  EXPECT_GT(smallest_clip, largest_rail);
  EXPECT_TRUE(ds4.friction);
  EXPECT_EQ(ds5.slide, 0.0);
  EXPECT_EQ(ds5.clear_waypoint, 1);  // a straight pull-out
  EXPECT_GT(ds1.slide, 0.0);
  for (const auto* t : {&ds1, &ds2, &ds3, &ds4, &ds5}) {
    for (const auto& p : t->parts) EXPECT_GT(p.volume, 0) << t->family << " " << p.name;
  }
}

TEST(ClipScenes, TriangleTargetsAndSeeds) {
  for (const std::int64_t target : {3000, 20000}) {
    const auto dir = testing::MakeTempDir("clip-count");
    ClipSceneOptions options;
    options.triangles = target;
    const ClipSceneFiles files = GenerateClipScene("clips-ds2", options, dir);
    const ClipGroundTruth truth = LoadClipGroundTruth(files.ground_truth_yaml);
    EXPECT_NEAR(static_cast<double>(truth.dynamic_triangles), static_cast<double>(target), 0.1 * target);
  }
  // Thesis counts by default (table 14), within a few percent.
  const auto dir = testing::MakeTempDir("clip-default");
  const ClipGroundTruth ds4 = LoadClipGroundTruth(GenerateClipScene("clips-ds4", {}, dir).ground_truth_yaml);
  EXPECT_NEAR(static_cast<double>(ds4.dynamic_triangles), 2448.0, 0.1 * 2448);
  EXPECT_NEAR(static_cast<double>(ds4.static_triangles), 4250.0, 0.1 * 4250);
  // The seed changes the scene; the same seed gives the same files.
  ClipSceneOptions a, b;
  a.seed = 1;
  b.seed = 2;
  const auto d1 = testing::MakeTempDir("clip-seed"), d2 = testing::MakeTempDir("clip-seed"),
             d3 = testing::MakeTempDir("clip-seed");
  GenerateClipScene("clips-ds3", a, d1);
  GenerateClipScene("clips-ds3", a, d2);
  GenerateClipScene("clips-ds3", b, d3);
  auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  EXPECT_EQ(read(d1 / "part.obj"), read(d2 / "part.obj"));
  EXPECT_NE(read(d1 / "part.obj"), read(d3 / "part.obj"));
  EXPECT_THROW(GenerateClipScene("clips-ds9", {}, d3), InputError);
}

TEST(ClipScenes, ColorValuesFollowTheLabels) {
  const ClipSceneData& data = ClipScene("clips-ds2");
  const std::vector<float> colors =
      ColorValues(data.voxels.dynamic_grid, data.scene.dynamic_mesh, data.truth.VertexDeformability());
  const VoxelGridGeometry& g = data.voxels.dynamic_grid.geometry;
  int clip_voxels = 0;
  for (std::int64_t v = 0; v < g.Count(); ++v) {
    if (data.voxels.dynamic_grid.cells[v] == kVoxelEmpty) {
      EXPECT_EQ(colors[v], 0.0f);
      continue;
    }
    const Vec3 p = g.Center(v);
    for (const auto& part : data.truth.parts) {
      if (part.kind == "clip" && part.overlap_box.Contains(p)) {
        EXPECT_LT(colors[v], 0.01f);
        ++clip_voxels;
      }
    }
  }
  EXPECT_GT(clip_voxels, 0);
  // The panel's middle is rigid.
  const Vec3 mid = data.scene.dynamic_origin;
  const Eigen::Vector3i c = ((mid - g.origin) / g.spacing).array().floor().cast<int>();
  EXPECT_FLOAT_EQ(colors[g.Index(c.x(), c.y(), c.z())], 1.0f);
}

TEST(ClipScenes, ShrinkRemovesTheBarbOverlap) {
  const ClipSceneData& data = ClipScene("clips-ds2");
  const double h = data.voxels.dynamic_grid.geometry.spacing;
  const VoxelGrid shrunk = ErodeVoxels(data.voxels.dynamic_grid, 3 * h);
  IntersectionVolume volume(data.voxels.static_grid, shrunk, data.scene.dynamic_origin);
  EXPECT_EQ(volume.Iv(data.truth.path.front()), 0.0);
  EXPECT_LT(shrunk.CountOccupied(), data.voxels.dynamic_grid.CountOccupied());
}

// ------------------------------------------------------------ artifact and stage

TEST(VoxelArtifact, RoundTrip) {
  const ClipSceneData& data = ClipScene("clips-ds4");
  const auto dir = testing::MakeTempDir("voxels");
  Provenance provenance{"test", "0", "a: 1\n", {{"scene", "x"}}};
  WriteVoxelArtifact(dir / "v.h5", data.voxels, {"ds4", "mm"}, provenance);
  VoxelArtifactInfo info;
  const SceneVoxels back = ReadVoxelArtifact(dir / "v.h5", &info);
  EXPECT_EQ(info.scene, "ds4");
  EXPECT_EQ(info.units, "mm");
  EXPECT_EQ(back.static_grid.cells, data.voxels.static_grid.cells);
  EXPECT_EQ(back.dynamic_grid.cells, data.voxels.dynamic_grid.cells);
  EXPECT_EQ(back.static_grid.geometry.dims, data.voxels.static_grid.geometry.dims);
  EXPECT_TRUE(back.static_grid.geometry.origin.isApprox(data.voxels.static_grid.geometry.origin));
  EXPECT_DOUBLE_EQ(back.dynamic_grid.geometry.spacing, data.voxels.dynamic_grid.geometry.spacing);
  EXPECT_TRUE(back.dynamic_grid.geometry.axes.isApprox(data.voxels.dynamic_grid.geometry.axes, 1e-15));
  EXPECT_TRUE(back.static_grid.geometry.axes.isApprox(data.voxels.static_grid.geometry.axes, 1e-15));
  EXPECT_THROW(ReadVoxelArtifact(dir / "missing.h5"), InputError);
}

// ------------------------------------------------------------ grids that fit

// A 60 x 40 x 3 panel with a 2 mm tongue, and a plate the tongue's tip
// overlaps (IV > 0 at the installed pose, the identity).
Scene PanelAndPlate() {
  Scene scene;
  scene.units = "mm";
  scene.dynamic_mesh = MakeBox({0, 0, 0}, {60, 40, 3});
  scene.dynamic_mesh.Append(MakeBox({55, 15, 3}, {57, 25, 12}));
  scene.static_mesh = MakeBox({50, -10, 9}, {80, 50, 11});
  return scene;
}

Scene Turned(const Scene& scene, const Eigen::Isometry3d& place) {
  Scene out = scene;
  for (Vec3& v : out.dynamic_mesh.vertices) v = place * v;
  for (Vec3& v : out.static_mesh.vertices) v = place * v;
  return out;
}

TEST(Voxelize, PrincipalAxesAreARightHandedFrameOfATurnedBox) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.8, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  std::vector<Vec3> points;
  for (const Vec3& v : MakeBox({0, 0, 0}, {60, 40, 3}).vertices) points.push_back(turn * v + Vec3(3000, -200, 900));
  const Eigen::Matrix3d axes = PrincipalAxes(points);
  EXPECT_TRUE((axes.transpose() * axes).isIdentity(1e-12));
  EXPECT_NEAR(axes.determinant(), 1.0, 1e-12);
  // Largest spread first: the box's 60 mm edge, then its 40 mm edge.
  EXPECT_NEAR(std::abs(axes.col(0).dot(turn.col(0))), 1.0, 1e-9);
  EXPECT_NEAR(std::abs(axes.col(1).dot(turn.col(1))), 1.0, 1e-9);
  EXPECT_NEAR(std::abs(axes.col(2).dot(turn.col(2))), 1.0, 1e-9);
}

TEST(Voxelize, ATurnedSceneGetsTheGridsAndTheVolumeOfTheAlignedOne) {
  // Car coordinates: the whole scene turned and 3 m out. D's and S's grids
  // lie in D's principal frame, so the voxel size, the grids' sizes and the
  // intersection volume at the installed pose are those of the aligned
  // scene (a world-aligned grid of the turned panel would be coarser: its
  // AABB holds many times its volume).
  const Scene aligned = PanelAndPlate();
  const Eigen::Isometry3d place =
      Eigen::Translation3d(3100, -450, 1200) * Eigen::AngleAxisd(2.1, Vec3(0.3, 1, -0.7).normalized());
  const Scene turned = Turned(aligned, place);
  VoxelizeOptions options;
  options.voxel_budget = 200000;
  const SceneVoxels a = VoxelizeScene(aligned, options), b = VoxelizeScene(turned, options);
  EXPECT_NEAR(b.dynamic_grid.geometry.spacing, a.dynamic_grid.geometry.spacing, 1e-9);
  EXPECT_EQ(b.dynamic_grid.geometry.dims, a.dynamic_grid.geometry.dims);
  EXPECT_EQ(b.static_grid.geometry.dims, a.static_grid.geometry.dims);
  const double world_aligned = AutomaticVoxelSize(turned.dynamic_mesh.Bounds(), options.voxel_budget);
  EXPECT_GT(world_aligned, 1.5 * b.dynamic_grid.geometry.spacing);
  IntersectionVolume volume_a(a.static_grid, a.dynamic_grid, aligned.dynamic_origin);
  IntersectionVolume volume_b(b.static_grid, b.dynamic_grid, turned.dynamic_origin);
  const double iv_a = volume_a.Iv(aligned.start), iv_b = volume_b.Iv(turned.start);
  EXPECT_GT(iv_a, 0);
  EXPECT_NEAR(iv_b, iv_a, 0.02 * iv_a);
  // And after the same motion (lift the tongue out by 5 mm along the panel's
  // normal, turned with the scene): nothing.
  Pose lifted_a = aligned.start, lifted_b = turned.start;
  lifted_a.t += Vec3(0, 0, -5);
  lifted_b.t += place.linear() * Vec3(0, 0, -5);
  EXPECT_EQ(volume_a.Iv(lifted_a), 0.0);
  EXPECT_EQ(volume_b.Iv(lifted_b), 0.0);
}

TEST(Voxelize, SIsVoxelizedWhereDCanReachNotWhereverSExtends) {
  // S: the plate, and a 20 m floor far from D (a whole vehicle). S's grid
  // covers D's neighbourhood; whole_static covers all of S.
  Scene scene = PanelAndPlate();
  scene.static_mesh.Append(MakeBox({-10000, -10000, -2000}, {10000, 10000, -1990}));
  VoxelizeOptions options;
  options.voxel_budget = 200000;
  const SceneVoxels near = VoxelizeScene(scene, options);
  const Aabb covered = near.static_grid.geometry.Bounds();
  const double reach = scene.dynamic_mesh.Bounds().Diagonal();
  const double h = near.static_grid.geometry.spacing;
  EXPECT_LT(covered.Size().maxCoeff(), 1.1 * (scene.dynamic_mesh.Bounds().Size().maxCoeff() + 2 * reach) + 4 * h);
  EXPECT_TRUE(covered.Contains(Vec3(56, 20, 10)));  // where the tongue meets the plate
  // All of S (at a voxel size that fits it): the floor's corners too.
  options.whole_static = true;
  options.voxel_size = 100;
  const Aabb whole = VoxelizeScene(scene, options).static_grid.geometry.Bounds();
  EXPECT_TRUE(whole.Contains(Vec3(-9999, -9999, -1995)));
  EXPECT_TRUE(whole.Contains(Vec3(9999, 9999, -1995)));
}

std::pair<int, std::string> RunCommand(const std::string& command) {
  std::string output;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  char buf[4096];
  while (fgets(buf, sizeof buf, pipe) != nullptr) output += buf;
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), output};
}

TEST(VoxelizeStage, WritesCachesAndRefusesHugeGrids) {
  const auto exe = testing::BinDir() / "ausbau-voxelize";
  if (!std::filesystem::exists(exe)) GTEST_SKIP() << exe << " not built";
  const auto dir = testing::MakeTempDir("voxelize-stage");
  ClipSceneOptions options;
  options.triangles = 3000;
  const auto scene = GenerateClipScene("clips-ds5", options, dir).scene_yaml;
  const std::string base = exe.string() + " --scene " + scene.string() + " -o " + (dir / "v.h5").string();
  auto [rc, out] = RunCommand(base);
  ASSERT_EQ(rc, 0) << out;
  const SceneVoxels voxels = ReadVoxelArtifact(dir / "v.h5");
  EXPECT_GT(voxels.dynamic_grid.CountOccupied(), 1000);
  std::tie(rc, out) = RunCommand(base);
  EXPECT_EQ(rc, 0);
  EXPECT_NE(out.find("up to date"), std::string::npos) << out;
  std::tie(rc, out) = RunCommand(base + " --voxel-size 0.001");
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("--memory-limit"), std::string::npos) << out;
  // The automatic size gives way to the memory limit (coarser, with a
  // warning) rather than failing: 2 MiB fits only a coarse grid.
  std::tie(rc, out) = RunCommand(exe.string() + " --scene " + scene.string() + " -o " + (dir / "coarse.h5").string() +
                                 " --memory-limit 0.002");
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("coarsened"), std::string::npos) << out;
  const SceneVoxels coarse = ReadVoxelArtifact(dir / "coarse.h5");
  EXPECT_GT(coarse.dynamic_grid.geometry.spacing, voxels.dynamic_grid.geometry.spacing);
  EXPECT_LE(6.0 * (coarse.dynamic_grid.geometry.Count() + coarse.static_grid.geometry.Count()), 0.002 * (1 << 30));
  std::tie(rc, out) = RunCommand(base + " --shrink 1 --voxel-size 0.8 --force");
  EXPECT_EQ(rc, 0) << out;
  const SceneVoxels shrunk = ReadVoxelArtifact(dir / "v.h5");
  EXPECT_DOUBLE_EQ(shrunk.shrink, 1.0);
  std::tie(rc, out) = RunCommand(base + " --voxel-size -1");
  EXPECT_EQ(rc, 2) << out;
}

}  // namespace
}  // namespace ausbau
