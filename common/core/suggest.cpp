#include "core/suggest.h"

#include <algorithm>
#include <cctype>

namespace ausbau {
namespace {

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// Optimal string alignment distance (Levenshtein plus adjacent swaps).
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

}  // namespace

std::string ClosestName(const std::string& given, const std::vector<std::string>& known) {
  // Long input (a pasted line) is no typo, and the table would be large.
  if (given.empty() || given.size() > 200) return "";
  const std::string g = Lower(given);
  const std::size_t allowed = g.size() <= 4 ? 1 : g.size() <= 8 ? 2 : 3;
  std::string best;
  std::size_t best_distance = allowed + 1;
  for (const std::string& name : known) {
    if (name.size() > 200) continue;
    if (name == given) continue;
    const std::string n = Lower(name);
    std::size_t distance = EditDistance(g, n);
    if (g.size() >= 3 && n.compare(0, g.size(), g) == 0) distance = std::min(distance, allowed);
    if (distance < best_distance) {
      best_distance = distance;
      best = name;
    }
  }
  return best;
}

}  // namespace ausbau
