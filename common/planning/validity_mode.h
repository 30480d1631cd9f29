// The validity modes: how a pose of D is judged valid. Parsed once, where a
// mode comes in as text (--validity, the attribute `validity` of a path or
// tau artifact); the library passes the enum. The names are the spelling of
// the flag and of the artifacts, and never change (goldens compare them).
//   rigid-exact             D's rigid shells never deeper in S than the
//                           tolerance, its fasteners free (collision/rigid_depth.h)
//   collision               rigid planning from a collision-free start
//   shrink, iv, mliv,       the volume modes of InIState planning (thesis 5.3,
//   labeled-mliv,           5.4; inistate/volume_model.h): an intersection
//   labeled-mliv-unguarded  volume of D with S below tau
#pragma once

#include <string>
#include <vector>

namespace ausbau {

enum class ValidityMode { kRigidExact, kCollision, kShrink, kIv, kMliv, kLabeledMliv, kLabeledMlivUnguarded };

// Every mode, in the order above (ausbau-plan --validity).
const std::vector<std::string>& ValidityModeNames();
// Collision and the volume modes, the ones InIState knows (ausbau-tau-estimate --validity).
const std::vector<std::string>& InIStateValidityNames();

std::string ValidityModeName(ValidityMode mode);
// The mode of that name; throws InputError "<where>: unknown mode '<name>'
// (expected rigid-exact, collision, ...)" for any other text (where: the
// file and attribute it was read from; without it: --validity).
ValidityMode ParseValidityMode(const std::string& name, const std::string& where);
ValidityMode ParseValidityMode(const std::string& name);

// Whether a mode is a volume mode (shrink, iv, mliv, labeled-...): then a
// path carries tau, psi and per-waypoint volumes.
inline bool IsVolumeValidity(ValidityMode mode) {
  return mode != ValidityMode::kCollision && mode != ValidityMode::kRigidExact;
}

}  // namespace ausbau
