// The report's HTML page around the viewer's data (report.cpp builds the
// data; viewer.js draws from it).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "planning/state_space.h"
#include "report/report.h"
#include "report/report_headline.h"
#include "report/report_paths.h"
#include "report/report_util.h"
#include "scene/scene.h"

namespace ausbau::report_internal {

struct PageInputs {
  const ReportOptions& options;
  const ReportAssets& assets;
  const Scene& scene;
  const PlanningProblem& problem;
  const std::vector<PathEntry>& paths;
  const std::vector<std::pair<std::string, std::string>>& artifacts;  // run folder: name, status (HTML)
  const Headline& headline;
  const std::string& data;  // the JSON the viewer reads
  const BufferStore& store;
};

std::string ReportPageHtml(const PageInputs& in);

}  // namespace ausbau::report_internal
