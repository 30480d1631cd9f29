// The figures an engineer judges a path by (verdict.json's `path_quality`):
// how far D travels and turns, how direct that is, and how close it comes
// to S, per segment and where closest; and where it comes closer than the
// clearance the path was planned and smoothed to keep (--clearance).
#pragma once

#include <string>
#include <vector>

#include "planning/clearance.h"
#include "planning/path_io.h"
#include "scene/scene.h"

namespace ausbau {

struct PathQuality {
  double translation = 0;  // D's reference point's travel, scene units
  double rotation = 0;     // summed rotation angle, rad
  double straight = 0;     // distance between the reference point's ends, scene units
  double ratio = 0;        // translation / straight (NaN when the ends coincide)
  // The part of D measured ("rigid shells of D" for rigid-exact paths,
  // else "D"), and the first segment where clearance is asked for (InIState
  // paths: sigma_2, from c_inter; sigma_1 intersects S by design).
  std::string measured_part;
  int first_rigid_segment = 0;
  double clearance_kept = 0;  // the path artifact's --clearance (scene units; NaN: not recorded)
  // Per segment: the smallest clearance at the profile's dense poses
  // (workflow/path_profile.h), scene units; 0 in contact.
  std::vector<double> segment_clearance;
  // The smallest over segments >= first_rigid_segment, with where: the
  // segment, the fraction of it, the path parameter s (normalized length
  // from the start) and the nearest points of D and S (world).
  ClearanceSample min;
  double min_s = 0;
  // Segments >= first_rigid_segment whose clearance is below clearance_kept.
  std::vector<int> below;
};

// Measures the path artifact's waypoints (interpolated about its reference
// point, as planned) in `scene`; `rigid_tolerance_mm` classifies D's shells
// for a rigid-exact path (`classified`: see PathClearanceRobot).
PathQuality MeasurePathQuality(const Scene& scene, const PathArtifact& path, double rigid_tolerance_mm,
                               const PartModel* classified = nullptr);

// The `path_quality` object of verdict.json (schemas/verdict.md).
std::string PathQualityJson(const PathQuality& quality);

// One line for people: the figures, and the segments below the clearance
// kept (a warning where there are any).
std::string PathQualityLine(const PathQuality& quality, const std::string& units);
std::string ClearanceWarning(const PathQuality& quality, const std::string& units);

}  // namespace ausbau
