// The hard rigid constraint: D's rigid part may never penetrate S deeper
// than a tolerance, measured exactly on the meshes, however thin S is.
//
// Which part of D is rigid (the rule; docs/rigid-exact.md):
// D and S are split into shells (geometry/shells.h: the closed solids a CAD
// export is made of). Chapter 5 of the thesis rests on one premise: where D
// intersects S at the installed pose, a fastener (a snap clip, a friction
// fit) is deformed. So
//  1. the anchor is D's largest shell (by volume): the body the fasteners
//     hang from. It is always rigid;
//  2. a shell of D that penetrates S deeper than the tolerance at the
//     installed pose, measured (see UnmeasuredInterference), is a fastener,
//     and so is every shell of D that overlaps a fastener (a clip's beam
//     under its hook), growing through overlaps but never through the
//     anchor;
//  3. every other shell is rigid: ribs, rails, pins, the panel, and a solid
//     block or peg (one shell: the anchor). Nothing is deformable unless it
//     is already deformed at the installed pose.
// When the anchor, or a shell whose interference is not measured,
// penetrates S at the installed pose,
// D cannot come out without cutting: `rigid_interference` says which.
// Fasteners are not limited here: a clip bends as far as its removal needs
// (passing the rim, its hook overlaps S by its whole reach, more than at the
// installed pose), and only the rigid part decides. Their penetration is
// measured and reported; cluster_limit is the hook for a bound (infinite).
//
// Depth: for two convex shells, the exact separating-axis penetration depth
// (the shortest translation that separates them; ConvexSignedDepth). A pair
// with a non-convex or open shell: the surface depth of collision/mesh_depth.h
// (how deep either surface reaches into the other), an upper bound within a
// tenth of the limit; pairs whose triangles do not intersect (FCL) and that
// do not contain one another are separated by FCL's distance.
//
// Fit interference (a press fit, or tessellation overlap in a CAD export):
// a rigid shell of D that penetrates a shell of S deeper than the tolerance
// at the installed pose, where the overlap is a thin layer along a surface
// and small against the parts (FitRule), may stay that deep: that pair's
// limit is its installed depth plus the checker's limit, so the part can be
// drawn out along the fit but never pushed deeper. Any other rigid
// interference is a clash: not removable without cutting.
//
// Poses are those of the frame the robot mesh is given in (the planning
// convention for planners, the scene convention for the final check).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "collision/mesh_depth.h"
#include "collision/validity.h"
#include "geometry/mesh.h"
#include "geometry/shells.h"

namespace ausbau {

enum class ShellRole { kRigid, kFastener };

// When a rigid shell's installed interference with a shell of S is a fit
// interference (see above). Default (max_depth_mm < 0): the depth d is at
// most 5% of the smaller shell's box diagonal ("small against the parts")
// and the surface that overlaps deeper than the tolerance has an area of at
// least 100 d^2 ("a thin layer along a surface": a press-fit or
// tessellation overlap; a clip's hook or a part inside a wall is as deep as
// it is wide). max_depth_mm >= 0 (the scene key `fit_interference`):
// every interference up to that depth is a fit, deeper ones clashes (0: none
// is a fit).
struct FitRule {
  double max_depth = -1;  // scene units; < 0: the default rule
  // The meshes' chord error (scene units; 0: unknown): with the default
  // rule, an installed interference no deeper than this is a fit whatever
  // its shape, since surfaces touching in CAD overlap that deep after
  // tessellation (a bore's polygon lies inside the bore).
  double tessellation_depth = 0;
  static constexpr double kShareOfSize = 0.05;
  static constexpr double kAreaPerDepthSquared = 100;
  // And it slides out: along some direction d the overlapping surfaces lie
  // parallel to d, the area-weighted mean of (n . d)^2 over their normals
  // n at most this. A press fit's layer: only its rim (depth x perimeter
  // against its two faces) is across d, a few percent (a pin in its bore,
  // a block pressed into a wall: 0.02-0.04); an interlock is across every
  // direction (a nut's thread flanks in the bolt's, 60 degrees off the
  // axis: 0.25), and is a clash however thin.
  static constexpr double kMaxAcrossRelease = 0.1;
};

// A rigid pair allowed its installed depth.
struct FitInterference {
  int robot_shell = -1, static_shell = -1;
  double installed_depth = 0;                         // an upper bound (scene units)
  double area = 0;                                    // of the surface overlapping deeper than the tolerance
  Eigen::Vector3d release = Eigen::Vector3d::Zero();  // world: the direction it slides out along (up to sign)
};

// A fastener moulded into a rigid shell (docs/rigid-exact.md "Moulded
// fasteners"): a feature standing out of a plate-like shell
// (geometry/protrusions.h) that intersects S at the installed pose. Its box
// is left out of the shell's rigid check (DepthMask, mesh_depth.h); the rest
// of the shell is rigid. Fasteners are not limited, as separate fastener
// shells are not.
struct MouldedFastener {
  int shell = -1;
  TurnedBox box;               // in the frame of the robot shells
  int side = 1;                // the box's face on the plate: at -half.z along its third axis (1), or +half.z (-1)
  int triangles = 0;           // of the shell, wholly in the box
  double volume = 0;           // the feature's
  double installed_depth = 0;  // how deep the shell reaches into S at the installed pose with only this feature counted
};

// When features of a plate-like shell may be moulded fasteners: a fastener
// is small against the part it holds (a snap clip on a panel, not the leg of
// a bracket): each feature at most kMaxShareOfShell of the shell's volume.
struct MouldedRule {
  static constexpr double kMaxShareOfShell = 0.05;
};

struct ShellModels;  // rigid_depth.cpp

struct PartModel {
  std::vector<Shell> robot_shells;      // D, in the frame its poses refer to
  std::vector<Shell> static_shells;     // S, world
  std::vector<ShellRole> role;          // per robot shell
  std::vector<int> cluster;             // per robot shell: fastener cluster, -1 for rigid
  std::vector<double> cluster_limit;    // per cluster: the depth it may reach (infinite: not limited)
  std::vector<double> installed_depth;  // per robot shell: deepest penetration of S at the installed pose
  int anchor = -1;                      // index of the anchor shell
  std::vector<int> rigid_interference;  // rigid shells that clash with S at the installed pose
  std::vector<FitInterference> fits;    // rigid pairs allowed their installed depth
  // Pairs that overlap at the installed pose by no more than the tolerance
  // (a peg pressed 0.03 mm into its hole's wall, a square lead's corners in
  // a round hole, a tessellation overlap): robot shell, static shell and
  // that depth (area and release not measured). A checker lets such a pair
  // stay that deep plus half its limit (OverlapDepth), or one whose limit
  // is below the depth (the planners': half the tolerance) would call the
  // installed pose itself invalid.
  std::vector<FitInterference> overlaps;
  std::vector<MouldedFastener> moulded;  // fasteners moulded into rigid shells
  // Per robot shell: the boxes of its moulded fasteners (null: none).
  std::vector<std::shared_ptr<const DepthMask>> masks;
  // Why a rigid shell that clashes was not split into moulded fasteners
  // (empty: not tried or split).
  std::string moulded_note;
  // Shells other than the anchor deeper than the tolerance at the installed
  // pose in a pair with a non-convex shell (a clip in a plate with holes
  // welded into one mesh, or a friction-fit rail there): ChooseValidity
  // hands those scenes to the volume model.
  std::vector<int> non_convex_interference;
  // Pairs (robot shell, static shell) with a non-convex shell whose
  // surfaces are within the tolerance of each other at the installed pose
  // (a part on its seat, a fit, a clip in its hole): sorted, for
  // NewContacts::kCollide.
  std::vector<std::pair<int, int>> installed_contacts;
  // Per static shell: the solid of S it belongs to. Shells that overlap or
  // touch (within the tolerance) are one solid: a plate tiled of boxes with
  // a rib on it is one, a neighbouring part apart from it another.
  std::vector<int> static_solid;
  // The solids of S a fastener engages at the installed pose (penetrates
  // deeper than the tolerance), sorted: per fastener cluster, and per robot
  // shell with moulded fasteners (empty elsewhere). A fastener bends into
  // those only: any other solid of S (a wall, a rib or a part it does not
  // hold on to) is to it what it is to a rigid shell (docs/rigid-exact.md
  // "Fasteners stay physical").
  std::vector<std::vector<int>> cluster_engages;
  std::vector<std::vector<int>> mask_engages;
  double tolerance = 0;  // the one used to classify
  // The shells' models for measuring (FCL trees, depth surfaces, slab
  // axes; rigid_depth.cpp), built by ClassifyParts for its own
  // measurements and reused by every RigidDepthChecker of this model: on
  // CAx-IF s1's head (S about 300,000 triangles) each build took 3.4 s,
  // four per ausbau-plan run. Null (a model made by hand): each checker
  // builds its own.
  std::shared_ptr<const ShellModels> shell_models;

  // Whether robot shell r's fasteners (a fastener shell's cluster, or the
  // moulded fasteners of a rigid shell) may bend into static shell s.
  bool Engages(int robot_shell, int static_shell) const;

  bool InstalledContact(int robot_shell, int static_shell) const;

  // The installed depth a fit allows the pair, or 0.
  double FitDepth(int robot_shell, int static_shell) const;
  // The pair's installed overlap within the tolerance (`overlaps`), or 0.
  double OverlapDepth(int robot_shell, int static_shell) const;

  int FastenerCount() const;  // fastener shells and moulded fasteners
  const DepthMask* Mask(int shell) const {
    return shell < static_cast<int>(masks.size()) ? masks[shell].get() : nullptr;
  }
  // "shell 3 (convex, 12 triangles, centre [x, y, z])": how a report names a
  // shell of D (robot = true) or of S.
  std::string Describe(int shell, bool robot) const;
};

// An interference at the installed pose of a shell other than the anchor
// in a pair with a non-convex shell (e.g. a plate with holes welded into one
// mesh): a snap clip there, or a friction-fit rail that must not be pushed
// deeper (clips-ds4)? Alone, the exact check tells them by FitRule (kRigid:
// a fit stays rigid, the rest are fasteners); where a volume model bounded
// every intersection while planning (the volume modes), the exact check
// leaves all of them to that model as fasteners (kFastener). (The name is
// from before such depths were measured.)
enum class UnmeasuredInterference { kRigid, kFastener };

// Splits D and S into shells and classifies D's shells at `installed` (the
// start pose, in the robot mesh's frame). `tolerance` in scene units. S's
// shells and models are kept for the next classification of the same S (the
// same triangles and crop box): a stage classifies one S for its search and
// again for the exact check of what it writes (D in another frame), and S is
// nearly all of the work (the last few S's are kept, together up to 2
// million triangles).
std::shared_ptr<const PartModel> ClassifyParts(const TriangleMesh& robot, const TriangleMesh& environment,
                                               const Pose& installed, double tolerance,
                                               UnmeasuredInterference unmeasured = UnmeasuredInterference::kRigid,
                                               const FitRule& fit = {});

// Whether two classifications share S's models (the same S classified
// again), and so measure S from the same trees and surfaces.
bool SharesStaticModels(const PartModel& a, const PartModel& b);

struct DepthReport {
  // Deepest penetration of a rigid shell into S (> 0), or minus a lower bound
  // on the smallest rigid gap measured (<= 0); -infinity when no rigid shell
  // is within the broad phase margin. +infinity: a non-convex pair intersects.
  double rigid_depth = -std::numeric_limits<double>::infinity();
  int rigid_shell = -1, rigid_static_shell = -1;
  // A pair with an installed fit interference (PartModel::fits) counts in
  // rigid_depth only by how far it is deeper than installed, and one with an
  // installed overlap allowed more than the limit (PartModel::overlaps) by
  // how far it is deeper than that allowance less the limit; their depth
  // itself is fit_depth.
  double fit_depth = 0;
  double fastener_depth = 0;  // deepest fastener penetration (reported, not judged)
  // min over measured pairs of (allowed depth - depth); >= 0 valid.
  double slack = 0;
};

// How a motion check treats a pair with a non-convex shell that is not in
// contact at the installed pose (PartModel::installed_contacts) once its
// surfaces meet:
//   kMeasure  its depth is measured and allowed up to the limit (the exact
//             check of a written path, reports);
//   kCollide  it is a collision (the planners and the smoother). Measuring
//             a shallow contact of non-convex surfaces to within the
//             planners' limit is a branch and bound over sub-triangles:
//             0.3-3 ms a pair, against some 20 us to see that the surfaces
//             meet (measured on a moulded T-key in its channel). Contacts
//             the installed pose has (a part resting on its seat, a fit,
//             a moulded clip) are still measured, and convex pairs always
//             (exactly, in microseconds). A path planned so passes the
//             exact check a fortiori; what it gives up is a passage that
//             only a new non-convex contact within the tolerance opens.
enum class NewContacts { kMeasure, kCollide };

class RigidDepthChecker : public SlackValidity {
 public:
  // `limit`: the rigid depth this check allows (the planners use half the
  // tolerance, so that the final check at the full tolerance has room);
  // `min_step`: the conservative-advancement floor (a motion check then
  // guarantees limit + min_step between its poses).
  RigidDepthChecker(std::shared_ptr<const PartModel> parts, double limit, double min_step,
                    NewContacts new_contacts = NewContacts::kMeasure);
  ~RigidDepthChecker() override;

  DepthReport Measure(const Pose& pose) const;
  // What a motion check asks, cheaper than Measure: the slack (to a step's
  // precision) and, once one pair is deeper than it may be, that pair with
  // a lower bound on its depth, the others not measured. Fasteners are not
  // reported.
  DepthReport MeasureUntilTooDeep(const Pose& pose) const { return MeasurePairs(pose, false); }
  double MinStep() const override { return min_step_; }
  bool ProvesTranslations() const override { return true; }
  double limit() const { return limit_; }
  const PartModel& parts() const { return *parts_; }

 protected:
  double Slack(const Pose& pose) const override;
  // Slack(pose) >= 0, answered without distances (a non-convex pair that
  // does not intersect is valid; its distance only matters for the slack).
  bool CheckValid(const Pose& pose) const override;
  // Every pair within reach of the motion proved not to exceed its allowed
  // depth anywhere on it (PairMeasure::SweepMayExceed): the same rules as
  // CheckValid, for all poses of the translation at once.
  bool TranslationValid(const Pose& pose, const Eigen::Vector3d& move) const override;

 private:
  DepthReport MeasurePairs(const Pose& pose, bool report_fasteners) const;
  // How pair (robot shell, static shell) is judged: the depth allowed
  // (infinite: not limited), whether the robot shell counts with its
  // moulded fasteners (a solid of S they do not engage), and whether the
  // depth is a fastener's (reported, not a rigid depth).
  struct PairRule {
    double allowed = 0;
    bool whole = false;
    bool fastener = false;
  };
  PairRule Rule(int robot_shell, int static_shell) const;
  // NewContacts::kCollide, a rigid shell, and no contact at the installed
  // pose (only a pair with a non-convex shell asks).
  bool ContactCollides(int robot_shell, int static_shell) const {
    return new_contacts_ == NewContacts::kCollide && parts_->role[robot_shell] == ShellRole::kRigid &&
           !parts_->InstalledContact(robot_shell, static_shell);
  }
  struct Impl;
  std::shared_ptr<const PartModel> parts_;
  double limit_, min_step_, margin_;
  NewContacts new_contacts_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ausbau
