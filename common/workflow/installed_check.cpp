#include "workflow/installed_check.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "collision/fcl_checker.h"
#include "collision/rigid_depth.h"
#include "collision/scene_parts.h"
#include "core/format.h"

namespace ausbau {
namespace {

SceneFinding Finding(SceneFinding::Severity severity, const std::string& code, const std::string& message) {
  SceneFinding finding;
  finding.severity = severity;
  finding.code = code;
  finding.message = message;
  return finding;
}

// The part of S a static shell belongs to (its first triangle's), in words.
std::string StaticPartName(const Scene& scene, const Shell& shell) {
  if (shell.source_triangles.empty()) return "S";
  const int triangle = shell.source_triangles.front();
  if (triangle < 0 || triangle >= static_cast<int>(scene.static_part_of_triangle.size())) return "S";
  const int part = scene.static_part_of_triangle[triangle];
  if (part < 0 || part >= static_cast<int>(scene.static_part_names.size())) return "S";
  return scene.static_part_names[part];
}

// The parts of S a robot shell overlaps deeper than the tolerance, or
// touches, at the installed pose (PartModel::installed_contacts holds the
// pairs with a non-convex side; the rest are found by the depth).
std::string PartsNear(const Scene& scene, const PartModel& parts, int robot_shell) {
  std::set<std::string> names;
  for (const auto& [r, s] : parts.installed_contacts)
    if (r == robot_shell) names.insert(StaticPartName(scene, parts.static_shells[s]));
  if (names.empty()) return "S";
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

}  // namespace

std::vector<SceneFinding> CheckInstalledPose(const Scene& scene, const InstalledCheckOptions& options) {
  std::vector<SceneFinding> findings;
  if (scene.goal) return findings;  // a motion task: the start need not be installed
  const std::string& units = scene.units.empty() ? std::string("units") : scene.units;
  const double tolerance = RigidToleranceInSceneUnits(options.rigid_tolerance_mm, scene, nullptr);
  const auto parts = ClassifySceneParts(scene, tolerance, UnmeasuredInterference::kRigid);
  using S = SceneFinding::Severity;

  for (const int r : parts->rigid_interference) {
    findings.push_back(Finding(
        S::kWarning, "installed-clash",
        Fmt("a rigid solid of D (%s) is %.3g %s deep in %s at the installed pose, deeper than a fit may be (a thin "
            "layer that slides out, at most 5%% of the parts' size): the verdict will be \"not removable without "
            "cutting\" unless the start pose or the meshes are wrong",
            parts->Describe(r, true).c_str(), parts->installed_depth[r], units.c_str(),
            PartsNear(scene, *parts, r).c_str())));
  }
  for (const FitInterference& fit : parts->fits) {
    findings.push_back(Finding(
        S::kWarning, "installed-fit",
        Fmt("D overlaps %s by %.3g %s at the installed pose (its shell %d; the tolerance is %.3g %s): taken for a "
            "press fit or a tessellation overlap that slides out along [%.3f, %.3f, %.3f], allowed that deep along "
            "the path, never deeper; if the parts should not overlap, check the export's tessellation and the "
            "start pose",
            StaticPartName(scene, parts->static_shells[fit.static_shell]).c_str(), fit.installed_depth, units.c_str(),
            fit.robot_shell, tolerance, units.c_str(), fit.release.x(), fit.release.y(), fit.release.z())));
  }
  const int fasteners = parts->FastenerCount();
  if (fasteners > 0) {
    double deepest = 0;
    for (std::size_t r = 0; r < parts->role.size(); ++r)
      if (parts->role[r] == ShellRole::kFastener) deepest = std::max(deepest, parts->installed_depth[r]);
    findings.push_back(
        Finding(S::kInfo, "installed-fasteners",
                Fmt("%d fastener%s of D reach into S at the installed pose (deepest %.3g %s): clips or snap-fits, "
                    "planned out of the invalid start (chapter 5 of the thesis)",
                    fasteners, fasteners == 1 ? "" : "s", deepest, units.c_str())));
  }
  if (parts->rigid_interference.empty() && parts->fits.empty() && fasteners == 0) {
    // No interference: how close is S? A fit finer than the planner's step
    // is what sampling finds last (the straight pulls try it first).
    TriangleMesh robot = scene.dynamic_mesh;
    for (auto& v : robot.vertices) v -= scene.dynamic_origin;
    const FclCollisionChecker fcl(robot, scene.static_mesh);
    const double gap = fcl.Distance(scene.start);
    const double step = options.resolution * scene.dynamic_mesh.Bounds().Diagonal();
    if (gap <= tolerance) {
      findings.push_back(
          Finding(S::kInfo, "installed-contact",
                  Fmt("D touches S at the installed pose (within the tolerance of %.3g %s): contact, not an "
                      "interference",
                      tolerance, units.c_str())));
    } else if (gap < step) {
      findings.push_back(
          Finding(S::kWarning, "fit-finer-than-step",
                  Fmt("D is %.3g %s from S at the installed pose, a fit finer than the planner's check step of %.3g %s "
                      "(%.2g of D's diagonal): sampling rarely finds such a passage; straight pulls along D's axes are "
                      "tried first, and every path is checked exactly (rigid-exact) whatever the step",
                      gap, units.c_str(), step, units.c_str(), options.resolution)));
    }
  }
  return findings;
}

}  // namespace ausbau
