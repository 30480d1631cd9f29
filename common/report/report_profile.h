// profile.csv (ausbau-smooth --profile, workflow/path_profile.h) as the
// report reads it: tolerant of its header's growth. Lines starting with '#'
// are skipped; columns are found by the start of their names ("segment",
// "fraction", "volume", "clearance", so "clearance_mm" is found too); other
// columns are ignored; empty cells are missing values.
#pragma once

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace ausbau::report_internal {

struct ProfileRow {
  int segment = 0;
  double fraction = 0;
  double volume = std::numeric_limits<double>::quiet_NaN();     // the volume model's intersection
  double clearance = std::numeric_limits<double>::quiet_NaN();  // FCL distance
};

struct Profile {
  std::vector<ProfileRow> rows;
  std::string volume_column;  // the header's name for it ("volume", "volume_mm3", ...)
  bool has_volume = false;    // some row has a volume value
};

// Throws InputError naming the file (and line) where it cannot be read or
// lacks the segment and fraction columns.
Profile ReadProfileCsv(const std::filesystem::path& file);

}  // namespace ausbau::report_internal
