#include "report/report_profile.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "report/report_util.h"

namespace ausbau::report_internal {

namespace {

std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (const char c : line) {
    if (c == ',') {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  cells.push_back(Trim(cell));
  return cells;
}

// The first column whose name starts with `prefix`, or -1.
int Column(const std::vector<std::string>& header, const std::string& prefix) {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i].compare(0, prefix.size(), prefix) == 0) return static_cast<int>(i);
  }
  return -1;
}

// A cell as a number: NaN when empty or absent; false when it is not a number.
bool Cell(const std::vector<std::string>& cells, int column, double* value) {
  *value = std::numeric_limits<double>::quiet_NaN();
  if (column < 0 || column >= static_cast<int>(cells.size()) || cells[column].empty()) return true;
  char* end = nullptr;
  *value = std::strtod(cells[column].c_str(), &end);
  return end == cells[column].c_str() + cells[column].size();
}

}  // namespace

Profile ReadProfileCsv(const std::filesystem::path& file) {
  std::istringstream in(ReadTextFile(file));
  Profile profile;
  std::vector<std::string> header;
  std::string line;
  int segment = -1, fraction = -1, volume = -1, clearance = -1;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (Trim(line).empty() || Trim(line)[0] == '#') continue;
    if (header.empty()) {
      header = SplitCells(line);
      segment = Column(header, "segment");
      fraction = Column(header, "fraction");
      volume = Column(header, "volume");
      clearance = Column(header, "clearance");
      if (segment < 0 || fraction < 0) {
        throw InputErrorAt(file.string(), "line " + std::to_string(number) + ": no 'segment' and 'fraction' columns");
      }
      if (volume >= 0) profile.volume_column = header[volume];
      continue;
    }
    const std::vector<std::string> cells = SplitCells(line);
    ProfileRow row;
    double s = 0, f = 0;
    if (!Cell(cells, segment, &s) || !Cell(cells, fraction, &f) || !std::isfinite(s) || !std::isfinite(f) || s < 0 ||
        !Cell(cells, volume, &row.volume) || !Cell(cells, clearance, &row.clearance)) {
      throw InputErrorAt(file.string(), "line " + std::to_string(number) + ": not a row of numbers");
    }
    row.segment = static_cast<int>(s);
    row.fraction = f;
    profile.has_volume = profile.has_volume || std::isfinite(row.volume);
    profile.rows.push_back(row);
  }
  if (header.empty()) throw InputErrorAt(file.string(), "no header line");
  return profile;
}

}  // namespace ausbau::report_internal
