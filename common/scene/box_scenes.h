// CAD-like clip-fastened panel scenes built only from oriented boxes, with
// an exact description of every box beside the meshes, so that an exact,
// independent checker (the external benchmark set's oracle.py, which reads
// boxes.json) can judge any path, and with ground truth: per-triangle clip
// labels and a known disassembly path.
//
// They differ from the clips-ds* families (scene/clip_scenes.h) in what they
// test: small clearances (0.2-1 mm instead of 3 mm), motions that are not
// axis-aligned slides (a tilt about a rail, a narrow straight pull, an
// L-shaped channel), a world placement metres from the origin at a random
// orientation, and the external set's file layout. Families (units mm):
//   panel-tilt-slide     a trim panel held by 3-6 snap clips on one edge, a
//                        locating pin near them and an L-shaped guide rail
//                        on the opposite edge whose foot sits under a lip of
//                        S: tilt 1-2 degrees about the rail (clip side up,
//                        pin out), slide 4-7 mm to free the foot, lift out
//   panel-straight-pull  thick clips and 2-4 guide pins in sleeves with
//                        0.2-0.35 mm clearance per side: only a straight pull
//                        along the panel normal works (3 degrees off fails)
//   panel-channel        no clips, no initial intersection: a tongue under
//                        the roof of an L-shaped channel of S; slide along
//                        one leg, then the other, then lift out
//
// Layout of a scene folder (the external set's, inistate-external/README.md):
//   scene.yaml                  format ausbau-scene/1, static: [static.stl],
//                               dynamic: dynamic.stl (no dynamic_origin)
//   static.stl, dynamic.stl     binary STL, world frame, installed pose: one
//                               closed box shell after another (boxes are
//                               not merged; they overlap where parts join)
//   boxes.json                  format obb-v1: static, dynamic_rigid,
//                               dynamic_clips, dynamic_stl_box_order
//   scene.json                  description, parameters, statistics
//   truth/labels_per_triangle.txt   1 clip, 0 rigid, per triangle of dynamic.stl
//   truth/known_path.csv        x,y,z,qw,qx,qy,qz: p_world = R(q) p + t for
//                               the vertices p of dynamic.stl (slerp and lerp
//                               about the world origin between rows)
//   truth/dynamic_rigid.stl, truth/dynamic_clips.stl   D split by label
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

// "panel-tilt-slide", "panel-straight-pull", "panel-channel".
std::vector<std::string> BoxSceneFamilies();
bool IsBoxSceneFamily(const std::string& family);

// coarse: 12 triangles per box. fine: every face a grid of triangles with
// edges of at most kFineEdge mm and at least 4 x 4 cells, each box still a
// closed convex shell with shared vertices.
enum class BoxTessellation { kCoarse, kFine };
// identity: the design frame is the world frame (S's base plate top at
// z = 0). random: the whole assembly rotated by a uniformly random rotation
// and moved 2-4 m from the origin, as CAD exports in car coordinates are.
enum class BoxWorld { kIdentity, kRandom };

constexpr double kFineEdge = 2.0;

// Parse "coarse" | "fine" and "identity" | "random"; throw InputError.
BoxTessellation ParseBoxTessellation(const std::string& text);
BoxWorld ParseBoxWorld(const std::string& text);

struct BoxSceneOptions {
  std::uint64_t seed = 1;
  BoxTessellation tessellation = BoxTessellation::kCoarse;
  BoxWorld world = BoxWorld::kRandom;
};

// point = center + rotation u, |u_i| <= half_extents_i; the rotation's
// columns are the box's axes (a proper rotation).
struct OrientedBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
  std::string tag;
};

// The box moved by a pose (x -> q x + t).
OrientedBox Transformed(const OrientedBox& box, const Pose& pose);
std::array<Eigen::Vector3d, 8> Corners(const OrientedBox& box);

// Exact separating-axis test over the 15 axes of a box pair, signed as the
// oracle's depth: > 0 the boxes overlap and this is the penetration depth
// (the smallest translation that separates them); <= 0 they are disjoint
// (or touch) and minus this is a lower bound on their distance, exact where
// the closest features are parallel faces.
double BoxPenetration(const OrientedBox& a, const OrientedBox& b);
// Euclidean distance between two boxes (0 where they touch or overlap).
double BoxDistance(const OrientedBox& a, const OrientedBox& b);

// The closed triangle shell of a box, faces oriented outwards.
TriangleMesh BoxShell(const OrientedBox& box, BoxTessellation tessellation);

struct BoxScene {
  std::string family;
  BoxSceneOptions options;
  std::string description;
  // World frame, installed pose.
  std::vector<OrientedBox> static_boxes, rigid_boxes, clip_boxes;
  std::vector<int> clip_of_box;  // per clip box: which clip it belongs to (0-based)
  int clips = 0;
  // dynamic.stl holds box (rigid_boxes ++ clip_boxes)[order[k]] as its k-th
  // box (shuffled, so that file order tells nothing about the labels).
  std::vector<int> dynamic_box_order;
  Pose world;                      // design frame -> world frame
  Eigen::Vector3d pull_direction;  // world: the direction of the known path's last motion (S's normal)
  std::vector<Pose> path;          // the known path (p_world = q p + t), starting at the identity
  std::string path_summary;        // "tilt 1.52 deg about the rail, slide 5.1 mm, lift 312 mm"
  double min_clearance = 0;        // the family's smallest designed rigid clearance
  std::vector<std::pair<std::string, double>> parameters;  // what the seed chose
};

// Builds a scene; deterministic for (family, options). Throws InputError for
// an unknown family.
BoxScene BuildBoxScene(const std::string& family, const BoxSceneOptions& options);

struct BoxSceneFiles {
  std::filesystem::path scene_yaml, boxes_json, scene_json, labels, known_path;
};

// Writes the folder described above (created).
BoxSceneFiles WriteBoxScene(const BoxScene& scene, const std::filesystem::path& dir);
BoxSceneFiles GenerateBoxScene(const std::string& family, const BoxSceneOptions& options,
                               const std::filesystem::path& dir);

// Statistics of the installed pose.
struct BoxSceneContacts {
  double rigid_min_clearance = 0;   // exact distance, rigid boxes of D to S
  double rigid_min_separation = 0;  // the same from BoxPenetration (a lower bound)
  double max_clip_penetration = 0;  // deepest clip box / S box overlap
  int clip_static_overlapping_pairs = 0;
  std::vector<bool> clip_intersects;  // per clip: one of its boxes overlaps S
};
BoxSceneContacts InstalledContacts(const BoxScene& scene);

// The deepest penetration of a rigid box of D into a box of S along a path
// (world poses, interpolated as the scene files say), sampled so that no
// vertex of D moves more than `step` mm between checks. A check independent
// of the oracle, for tests and for the generator's own assertion.
double MaxRigidPenetration(const BoxScene& scene, const std::vector<Pose>& path, double step = 0.25);

}  // namespace ausbau
