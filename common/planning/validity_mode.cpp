#include "planning/validity_mode.h"

#include <algorithm>

#include "core/error.h"

namespace ausbau {

const std::vector<std::string>& ValidityModeNames() {
  // In the enum's order.
  static const std::vector<std::string> names = {
      "rigid-exact", "collision", "shrink", "iv", "mliv", "labeled-mliv", "labeled-mliv-unguarded"};
  return names;
}

const std::vector<std::string>& InIStateValidityNames() {
  static const std::vector<std::string> names(ValidityModeNames().begin() + 1, ValidityModeNames().end());
  return names;
}

std::string ValidityModeName(ValidityMode mode) { return ValidityModeNames().at(static_cast<std::size_t>(mode)); }

ValidityMode ParseValidityMode(const std::string& name, const std::string& where) {
  const auto& names = ValidityModeNames();
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string expected;
    for (std::size_t i = 0; i < names.size(); ++i) {
      expected += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    }
    throw InputError(where + ": unknown mode '" + name + "' (expected " + expected + ")");
  }
  return static_cast<ValidityMode>(it - names.begin());
}

ValidityMode ParseValidityMode(const std::string& name) { return ParseValidityMode(name, "--validity"); }

}  // namespace ausbau
