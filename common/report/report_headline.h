// The report's first line: REMOVABLE / NOT REMOVABLE and why, in one
// sentence, from verdict.json (ausbau-verdict) and the paths shown.
#pragma once

#include <string>
#include <vector>

#include "report/json_read.h"
#include "report/report_paths.h"

namespace ausbau::report_internal {

struct Headline {
  std::string verdict;   // "REMOVABLE", "NOT REMOVABLE" or "NO VERDICT"
  std::string sentence;  // why, one sentence (plain text)
  std::string css;       // "ok", "bad", "none"
};

// `verdict`: the parsed verdict.json, or null where there is none (then
// `verdict_problem` says why: absent, unreadable, not JSON). `shown`: the
// path the page shows first (may be null); `units` the scene's.
Headline MakeHeadline(const JsonValue* verdict, const std::string& verdict_problem, const PathEntry* shown,
                      const std::string& units);

std::string HeadlineHtml(const Headline& headline);

}  // namespace ausbau::report_internal
