// Comma-separated option values of the benchmarks ("a, b,c" -> {a, b, c}).
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace ausbau::bench {

// Items trimmed of spaces and tabs; empty items dropped.
inline std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

}  // namespace ausbau::bench
