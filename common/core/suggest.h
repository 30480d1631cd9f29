// "Did you mean": the known name closest to a mistyped one, for the errors
// on unknown flags, scene keys and problem-file keys.
#pragma once

#include <string>
#include <vector>

namespace ausbau {

// The element of `known` nearest to `given` by edit distance (insertions,
// deletions, substitutions and swaps of two neighbouring characters, case
// ignored) when it is near enough to be a typo: at most 1 edit for names up
// to 4 characters, 2 up to 8, 3 beyond; or `given` is a prefix of it (at
// least 3 characters). Ties go to the first in `known`. "" when none is.
std::string ClosestName(const std::string& given, const std::vector<std::string>& known);

}  // namespace ausbau
