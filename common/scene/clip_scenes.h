// Generated InIState benchmark scenes (thesis 5.2, table 14, figs. 33-35): a
// trim panel D held on a base plate S by snap-fit clips and guide rails, in
// collision at its installed pose only where the clips' barbs overlap the rims
// of S's holes. Each scene comes with ground truth: which triangles and
// vertices of D are clip geometry (deformable) and which are rigid, and a
// known disassembly path.
//
// Families (all units mm; `--seed` varies dimensions and layout a little):
//   clips-ds1  8 small clips + 1 L-rail: the clips' summed pull-through
//              overlap exceeds what the rail would overlap if D were lifted
//              straight (a plain intersection-volume threshold that lets the
//              clips through also lets the rail through its lip)
//   clips-ds2  3 small clips + 1 L-rail (the clips' overlap is below the rail's)
//   clips-ds3  6 large clips + 2 rails (an L-rail under a lip and a T-rail in
//              a keyhole slot of S); each clip is bigger than each rail
//   clips-ds4  2 small clips + 2 L-rails held by friction: the rails' feet
//              intersect the lips slightly at the installed pose
//   clips-ds5  4 thick, nearly rigid clips, no rails: a straight pull-out
// ds1-ds4 come out by sliding in -x (the rails leave their lips), then
// lifting in +z (the barbs are pulled through the holes); ds5 by lifting.
//
// Layout: S's base plate is z in [-plate, 0]; D's panel lies above it, its
// underside `gap` above S's top. A clip is a tongue hanging from the panel
// through a hole of S, ending below the plate in a barb that points away from
// the panel's centre line and reaches `overlap` beyond the hole's rim; its
// top lies `penetration` above the plate's underside. L-rails are a leg and a
// foot that reaches under the overhang of a bracket (post + overhang) standing
// on S; T-rails hang through the narrow part of a keyhole slot with their head
// below the plate. Rigid parts keep >= 3 mm from S (3 voxels and more at
// ausbau-voxelize's default voxel size), except ds4's friction fit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

// "clips-ds1" .. "clips-ds5".
std::vector<std::string> ClipSceneFamilies();
bool IsClipSceneFamily(const std::string& family);

struct ClipSceneOptions {
  std::uint64_t seed = 1;
  // Target triangle count of D (the panel is subdivided to reach it; S is
  // tessellated to the thesis's S/D ratio of the dataset). 0 = the dataset's
  // counts in thesis table 14 (2,448 to 67,134 for D). The result is within a
  // few percent of the target, never below the family's minimum (~150-450).
  // At most 2,000,000.
  std::int64_t triangles = 0;
};

// Indices [begin, end).
struct IndexRange {
  std::int64_t begin = 0, end = 0;
  bool Contains(std::int64_t i) const { return i >= begin && i < end; }
};

struct ClipScenePart {
  std::string name;                   // "panel", "rim", "clip-0", "rail-0", ...
  std::string kind;                   // panel | rim | clip | rail
  bool deformable = false;            // clip geometry
  double deformability = 0;           // nominal label in [0, 1]: thin clips 1, ds5's thick clips 0.35, rigid 0
  double volume = 0;                  // of the part's closed mesh, mm^3
  std::vector<IndexRange> triangles;  // into D's triangles (file order = LoadMesh order)
  std::vector<IndexRange> vertices;   // into D's vertices as LoadMesh returns them
  // Clips: the world box where the barb overlaps S at the installed pose
  // (empty box otherwise); rails: where a friction fit overlaps S (ds4).
  Aabb overlap_box;
};

struct ClipGroundTruth {
  std::string family;
  std::uint64_t seed = 0;
  std::int64_t dynamic_triangles = 0, dynamic_vertices = 0, static_triangles = 0;
  Eigen::Vector3d dynamic_origin = Eigen::Vector3d::Zero();
  std::vector<ClipScenePart> parts;
  // Summed over clips: the largest barb/plate overlap volume met while the
  // clips are pulled through (exact, from the barb profile), and what the
  // rails would overlap if D were lifted straight without sliding first.
  double clip_pull_overlap = 0;
  double rail_block_overlap = 0;
  double slide = 0;       // length of the sideways motion (0 for ds5)
  double lift_clear = 0;  // lift that pulls the clips (and T-heads) clear of S
  bool friction = false;  // ds4: rigid rails overlap S until they leave their lips
  // The known path (scene convention) and the first waypoint at which no
  // part of D overlaps S any more (after the clips have been pulled through).
  std::vector<Pose> path;
  int clear_waypoint = 0;

  // Per vertex of D: the nominal deformability of its part.
  std::vector<double> VertexDeformability() const;
  // Per triangle of D: true for clip geometry.
  std::vector<bool> ClipTriangleMask() const;
};

struct ClipSceneFiles {
  std::filesystem::path scene_yaml;         // scene.yaml (environment.obj, part.obj beside it)
  std::filesystem::path ground_truth_yaml;  // ground_truth.yaml
  std::filesystem::path ground_truth_path;  // ground_truth_path.csv (x,y,z,qw,qx,qy,qz, scene convention)
};

// Writes the scene and its ground truth into `dir` (created). Throws
// InputError for an unknown family or a triangle target out of range.
ClipSceneFiles GenerateClipScene(const std::string& family, const ClipSceneOptions& options,
                                 const std::filesystem::path& dir);

// Reads ground_truth.yaml (and the path CSV it names). Throws InputError.
ClipGroundTruth LoadClipGroundTruth(const std::filesystem::path& ground_truth_yaml);

}  // namespace ausbau
