// The length units a scene.yaml may name (`units:`), in one place: the
// exact check converts its tolerance in millimetres with them, and
// ausbau-scene-check judges D's size by them.
#pragma once

#include <cctype>
#include <optional>
#include <string>

namespace ausbau {

// Millimetres per scene unit for mm, cm, m and inch (with their spelled-out
// names, any case); nothing for an empty, unitless or unknown name.
inline std::optional<double> MillimetresPerUnit(const std::string& units) {
  std::string u;
  for (char c : units) u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (u == "mm" || u == "millimeter" || u == "millimetre" || u == "millimeters" || u == "millimetres") return 1.0;
  if (u == "cm" || u == "centimeter" || u == "centimetre" || u == "centimeters" || u == "centimetres") return 10.0;
  if (u == "m" || u == "meter" || u == "metre" || u == "meters" || u == "metres") return 1000.0;
  if (u == "in" || u == "inch" || u == "inches") return 25.4;
  return std::nullopt;
}

// The one rule for length flags (README "Flags"): every length flag is in
// millimetres and converted by the scene's units; where the scene has none
// (or unitless or unknown ones), the number is taken in scene units.
inline double MillimetresInSceneUnits(double millimetres, const std::string& units) {
  const std::optional<double> per_unit = MillimetresPerUnit(units);
  return per_unit ? millimetres / *per_unit : millimetres;
}

// What format ausbau-scene/2 accepts for a scene's `units:`: a name
// MillimetresPerUnit converts, or unitless / none (any case).
inline bool IsSceneUnitsName(const std::string& units) {
  if (MillimetresPerUnit(units)) return true;
  std::string u;
  for (char c : units) u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return u == "unitless" || u == "none";
}

}  // namespace ausbau
