// Deformability labels decided per solid of D, for parts made of several
// closed solids (CAD exports: a clip, a rib, a rail each its own closed box
// or boxes, overlapping the panel, triangles not merged).
//
// Why not PBD there: the surface simulation (pbd_label.h) can only tell a
// feature that bends from one that does not by its shape, and on such
// exports the shape does not tell a clip: a rib is a wall as thin as a clip's
// beam (1.7-2.4 mm against 1.5-3 mm on the inistate-external set, thinner in
// linear-thick) and as high. Measured with `ausbau-label-bench --scene`
// (ROC AUC of clip triangles against rigid ones): 0.23-0.82, with or without
// refinement (--refine 1), where 0.5 is chance.
//
// What does tell a clip is the premise of chapter 5 itself: D intersects S at
// its installed pose because its fasteners are deformed there. So the rule is
// the one the exact rigid check uses (collision/rigid_depth.h, ClassifyParts),
// one meaning for "deformable" in the whole pipeline:
//  - every solid of D that penetrates S at the installed pose deeper than the
//    rigid tolerance, measured, and every solid overlapping one (never
//    through the anchor, D's largest solid) is a fastener: its vertices get
//    deformability 1;
//  - every other solid is rigid: 0. A part with no installed intersection is
//    rigid everywhere: a solid block or peg is labelled rigid, and "nothing
//    is deformable" is an answer.
//  - a feature moulded into a plate-like solid that intersects S there
//    (collision/rigid_depth.h MouldedFastener) is a fastener too: the
//    vertices of its triangles get 1.
// The rule does not apply (PBD labels then, the thesis's method) where the
// installed intersection cannot be measured (a non-convex or open solid at
// the contact, e.g. one welded mesh for a panel with its clips, as clips-ds*)
// or where D has an open surface: `applies` is false and `reason` says why.
// Limit: a rigid part modelled as its own solid that is press-fit into S at
// the installed pose is taken for a fastener (a friction fit is one).
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace ausbau {

struct SolidLabels {
  bool applies = false;
  std::string reason;                 // why the rule applies or not (for the log)
  std::vector<double> deformability;  // per vertex of D as LoadScene returns it (when applies)
  int solids = 0;                     // closed solids of D
  int fasteners = 0;                  // of them, labelled deformable
};

// `tolerance` in scene units (RigidToleranceInSceneUnits).
SolidLabels LabelBySolids(const Scene& scene, double tolerance);

}  // namespace ausbau
