// printf-style formatting into a std::string (any length), for messages,
// tables and reports.
#pragma once

#include <string>

namespace ausbau {

std::string Fmt(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace ausbau
