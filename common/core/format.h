// printf-style formatting into a std::string (any length), for messages,
// tables and reports.
#pragma once

#include <string>
#include <string_view>

namespace ausbau {

std::string Fmt(const char* format, ...) __attribute__((format(printf, 1, 2)));

// `text` as it may be shown on a terminal: control characters (C0, DEL and
// the C1 range U+0080..U+009F) written as \x1b or \u009b, so that a name
// from a file (a part, a mesh, a file name) cannot move the cursor, clear
// the screen or set a window title. Everything else is kept as it is.
std::string TerminalSafe(std::string_view text);
// The same for a text of several lines: its line breaks are kept.
std::string TerminalSafeLines(std::string_view text);

}  // namespace ausbau
