// The report's first line: REMOVABLE / NOT REMOVABLE and why, in one
// sentence, from verdict.json (ausbau-verdict) and the paths shown.
#pragma once

#include <functional>
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

// Names a shell of D (robot) or S by its index, as PartNamer::Shell does.
using ShellNamer = std::function<std::string(int shell, bool robot)>;

// `verdict`: the parsed verdict.json, or null where there is none (then
// `verdict_problem` says why: absent, unreadable, not JSON). `shown`: the
// path the page shows first (may be null); `units` the scene's. Where
// `names` is given, the verdict's shells ("shell 7 (convex, 12 triangles,
// ...)", PartModel::Describe) are named by it instead.
Headline MakeHeadline(const JsonValue* verdict, const std::string& verdict_problem, const PathEntry* shown,
                      const std::string& units, const ShellNamer& names = nullptr);

// `text` with each "shell N (...)" of PartModel::Describe replaced by
// names(N, robot); the side is D unless " of S" follows it.
std::string NameShells(const std::string& text, const ShellNamer& names);

// A text of the verdict (the exact check's reason, what_blocks' summary) in
// plain words: its lengths with the scene's unit ("after 8.9 mm of free
// travel:", "0.05 mm deep"), segments as the waypoints they join, an
// unmeasured depth ("inf") in words.
std::string PlainVerdictText(const std::string& text, const std::string& units);

std::string HeadlineHtml(const Headline& headline);

}  // namespace ausbau::report_internal
