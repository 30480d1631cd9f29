// The page of a report: its header, headline, 3D view and controls, plots,
// per-waypoint table, statistics and scene tables.
#include "report/report_page.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/format.h"
#include "planning/scene_goal.h"
#include "report/report.h"

namespace ausbau::report_internal {

namespace {

double MinClearance(const std::vector<PoseMeasure>& measures) {
  double m = std::numeric_limits<double>::infinity();
  for (const PoseMeasure& p : measures) m = std::min(m, p.clearance);
  return m;
}

std::string StatsTable(const std::vector<PathEntry>& paths, const std::string& units) {
  Table t;
  t.header.push_back("");
  for (const auto& e : paths)
    t.header.push_back(HtmlEscape(e.key) + "<br><code>" + HtmlEscape(e.file.string()) + "</code>");
  auto row = [&](const std::string& name, auto cell) {
    std::vector<std::string> r{name};
    for (const auto& e : paths) r.push_back(cell(e));
    t.rows.push_back(r);
  };
  row("producer", [](const PathEntry& e) { return HtmlEscape(e.producer); });
  row("planner", [](const PathEntry& e) { return HtmlEscape(e.artifact.planner); });
  row("success", [](const PathEntry& e) { return std::string(e.artifact.success ? "yes" : "<b>no</b>"); });
  row("waypoints", [](const PathEntry& e) { return Int(e.artifact.waypoints.size()); });
  row("planning time", [](const PathEntry& e) {
    return std::isfinite(e.artifact.stats.time_s) ? Num(e.artifact.stats.time_s) + " s" : std::string("not recorded");
  });
  row("iterations", [](const PathEntry& e) { return Int(e.artifact.stats.iterations); });
  row("nodes", [](const PathEntry& e) { return Int(e.artifact.stats.nodes); });
  row("collision checks", [](const PathEntry& e) { return Int(e.artifact.stats.collision_checks); });
  row("invalid checks", [](const PathEntry& e) {
    const auto& s = e.artifact.stats;
    return Int(s.invalid_checks) +
           (s.collision_checks > 0 ? Fmt(" (%.1f%%)", 100.0 * s.invalid_checks / s.collision_checks) : std::string());
  });
  row("length (normalized, no unit)", [](const PathEntry& e) {
    return std::isfinite(e.artifact.length_normalized) ? Num(e.artifact.length_normalized)
                                                       : std::string("not measured");
  });
  // Missing values are said in words, numbers with their unit.
  row("length, translation", [&units](const PathEntry& e) {
    return e.length_translation && std::isfinite(*e.length_translation) ? LengthText(*e.length_translation, units)
                                                                        : std::string("not measured");
  });
  row("length, rotation", [](const PathEntry& e) {
    return e.length_rotation && std::isfinite(*e.length_rotation) ? AngleText(*e.length_rotation)
                                                                  : std::string("not measured");
  });
  row("min clearance at waypoints", [&units](const PathEntry& e) {
    const double m = e.at_waypoints.empty() ? std::nan("") : MinClearance(e.at_waypoints);
    return std::isfinite(m) ? LengthText(m, units) : std::string("not measured");
  });
  row("min clearance along the path", [&units](const PathEntry& e) {
    const double m =
        e.at_samples.empty() ? std::nan("") : std::min(MinClearance(e.at_samples), MinClearance(e.at_waypoints));
    return std::isfinite(m) ? LengthText(m, units) + Fmt(" (%zu poses)", e.at_samples.size() + e.at_waypoints.size())
                            : std::string("not measured");
  });
  row("max rigid penetration along the path", [&units](const PathEntry& e) {
    double deepest = -std::numeric_limits<double>::infinity();
    bool measured = false;
    for (const auto* v : {&e.at_waypoints, &e.at_samples}) {
      for (const PoseMeasure& m : *v) {
        if (std::isnan(m.rigid_depth)) continue;
        measured = true;
        deepest = std::max(deepest, m.rigid_depth);
      }
    }
    if (!measured) return std::string("not measured (no rigid model)");
    if (deepest == std::numeric_limits<double>::infinity()) return std::string("intersects (depth not measured)");
    return deepest > 0 ? LengthText(deepest, units) : std::string("no contact (0 ") + LengthUnit(units) + ")";
  });
  return TableHtml(t, "stats");
}

// "+z (scene key)", "+y (default for glTF/COLLADA data)".
std::string UpAxisText(const UpAxis& up) {
  return (up.axis[0] == '-' ? up.axis : "+" + up.axis) + " (" + up.source + ")";
}

std::string SceneTable(const Scene& scene, const PlanningProblem& problem) {
  Table t;
  t.header = {"scene", HtmlEscape(scene.name)};
  auto row = [&](const std::string& k, const std::string& v) { t.rows.push_back({k, v}); };
  row("file", "<code>" + HtmlEscape(scene.file.string()) + "</code>");
  if (!scene.units.empty()) row("units", HtmlEscape(scene.units));
  row("up axis", "<span id=\"up-axis\">" + HtmlEscape(UpAxisText(SceneUpAxis(scene))) + "</span>");
  std::string statics;
  for (const auto& f : scene.static_files)
    statics += (statics.empty() ? "" : ", ") + ("<code>" + HtmlEscape(f.string()) + "</code>");
  row("S (static)", statics + Fmt(": %zu triangles, %zu vertices", scene.static_mesh.triangles.size(),
                                  scene.static_mesh.vertices.size()));
  row("D (dynamic)", "<code>" + HtmlEscape(scene.dynamic_file.string()) + "</code>" +
                         Fmt(": %zu triangles, %zu vertices", scene.dynamic_mesh.triangles.size(),
                             scene.dynamic_mesh.vertices.size()));
  row("dynamic_origin", VectorText(scene.dynamic_origin) + (scene.dynamic_origin_given ? "" : " (default)"));
  row("reference point", VectorText(problem.reference_point));
  row("start", PoseText(scene.start));
  row("goal", scene.goal             ? PoseText(*scene.goal)
              : scene.goal_condition ? HtmlEscape(SceneGoal(scene).Describe())
                                     : std::string("none (disassembly: out of S's bounding box)"));
  row("bounds on t", VectorText(problem.bounds.min) + " .. " + VectorText(problem.bounds.max) +
                         (problem.bounds_given ? "" : " (derived)"));
  return TableHtml(t, "scene");
}

std::string ImportMap(const ReportAssets& assets) {
  const std::string three = Base64Encode(assets.three_module.data(), assets.three_module.size());
  const std::string orbit = Base64Encode(assets.orbit_controls.data(), assets.orbit_controls.size());
  return "<script type=\"importmap\">{\"imports\":{\"three\":\"data:text/javascript;base64," + three +
         "\",\"three/addons/controls/OrbitControls.js\":\"data:text/javascript;base64," + orbit + "\"}}</script>\n";
}

std::string HeadHtml(const PageInputs& in) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<meta name=\"generator\" content=\"ausbau-report " << AUSBAU_VERSION << ", three.js "
       << HtmlEscape(in.assets.three_version) << "\">\n"
       << "<title>Ausbau report: " << HtmlEscape(in.scene.name) << "</title>\n<style>" << kStyle << "</style>\n"
       << ImportMap(in.assets) << "</head>\n<body>\n";
  html << "<header><h1>Ausbau report: " << HtmlEscape(in.scene.name) << "</h1><p>S "
       << in.scene.static_mesh.triangles.size() << " triangles, D " << in.scene.dynamic_mesh.triangles.size()
       << " triangles";
  for (const auto& e : in.paths)
    html << "; " << HtmlEscape(e.key) << " path: " << e.artifact.waypoints.size() << " waypoints";
  html << ". Written by ausbau-report " << AUSBAU_VERSION << " (three.js " << HtmlEscape(in.assets.three_version)
       << ", inlined; works offline).</p></header>\n";
  return html.str();
}

std::string ViewHtml(const Scene& scene) {
  return "<div id=\"view\"><canvas id=\"canvas3d\"></canvas><div id=\"status\">loading…</div>"
         "<div id=\"legend\"></div><div id=\"measureinfo\"></div><div id=\"help\"><span id=\"upinfo\">up: " +
         HtmlEscape(UpAxisText(SceneUpAxis(scene))) +
         "</span><span id=\"viewhelp\"> · drag: orbit · right-drag: pan · wheel: zoom · space: play/pause · D orange, "
         "S "
         "blue, line: path of D's reference point · Measure: click two points</span></div></div>\n"
         "<div id=\"controls\">"
         "<button id=\"play\" type=\"button\">Play</button>"
         "<input id=\"scrubber\" type=\"range\" min=\"0\" max=\"1000\" step=\"1\" value=\"0\" aria-label=\"path "
         "position\">"
         "<span id=\"timeinfo\"></span>"
         "<label>speed <select id=\"speed\"><option value=\"0.25\">0.25×</option><option value=\"0.5\">0.5×</option>"
         "<option value=\"1\" selected>1×</option><option value=\"2\">2×</option><option value=\"4\">4×</option>"
         "</select></label>"
         "<label>path <select id=\"pathselect\"></select></label>"
         "<label>S opacity <input id=\"opacity\" type=\"range\" min=\"0\" max=\"1\" step=\"0.05\" "
         "value=\"0.35\"></label>"
         "<label><input id=\"showtrace\" type=\"checkbox\" checked> path line</label>"
         "<label><input id=\"showghosts\" type=\"checkbox\"> start/goal ghosts</label>"
         "<label>section <select id=\"section-axis\"><option value=\"\" selected>off</option>"
         "<option value=\"x\">x</option><option value=\"y\">y</option><option value=\"z\">z</option></select> "
         "<input id=\"section-pos\" type=\"range\" min=\"0\" max=\"1000\" step=\"1\" value=\"500\" "
         "aria-label=\"section plane position\"><span id=\"section-info\"></span></label>"
         "<button id=\"measure\" type=\"button\" aria-pressed=\"false\">Measure</button>"
         "</div>\n"
         "<div id=\"plots\"></div><p id=\"plotnote\"></p>\n";
}

// A link per path that downloads its CSV (a data: URL: no file beside the page).
std::string DownloadsHtml(const std::vector<PathEntry>& paths) {
  std::string html;
  for (const PathEntry& e : paths) {
    if (e.csv_text.empty()) continue;
    html += "<li><a id=\"download-" + HtmlEscape(e.key) + "\" class=\"download\" download=\"" + HtmlEscape(e.csv_name) +
            "\" href=\"data:text/csv;base64," + Base64Encode(e.csv_text.data(), e.csv_text.size()) + "\">" +
            HtmlEscape(e.key) + " path as CSV (" + HtmlEscape(e.csv_name) + ", " +
            Int(static_cast<std::int64_t>(e.artifact.waypoints.size())) + " waypoints, x,y,z,qw,qx,qy,qz)</a></li>";
  }
  return html.empty() ? "" : "<h2>Download</h2><ul id=\"downloads\">" + html + "</ul>\n";
}

}  // namespace

// What the page shows, as the page: header, headline, 3D view and its
// controls, the plots, the tables; `data` is the JSON the viewer reads.
std::string ReportPageHtml(const PageInputs& in) {
  std::ostringstream html;
  html << HeadHtml(in) << "<main>\n" << HeadlineHtml(in.headline) << ViewHtml(in.scene);
  html << "<section id=\"waypoint-section\"><h2>Waypoints</h2><p class=\"explain\">Per waypoint of the path shown: "
          "its pose (scene convention), the clearance to S, how deep D's rigid part and its clips go into S, and "
          "which parts of D and S touch (where the rigid part penetrates) or are nearest. Click a row to go "
          "there.</p><div id=\"waypointbox\"></div></section>\n";
  html << DownloadsHtml(in.paths);
  html << "<div class=\"grid\"><div><h2>Path statistics</h2>";
  if (in.paths.empty()) {
    html << "<p class=\"note\">No path given: the page shows the scene only.</p>";
  } else {
    html << StatsTable(in.paths, in.scene.units);
  }
  html << "</div><div><h2>Scene</h2>" << SceneTable(in.scene, in.problem) << "</div></div>\n";
  html << "<div id=\"jsontables\"></div>\n";
  if (!in.options.run_dir.empty()) {
    Table t;
    t.header = {"file", "status"};
    for (const auto& [name, status] : in.artifacts) t.rows.push_back({"<code>" + HtmlEscape(name) + "</code>", status});
    html << "<h2>Run folder <code>" << HtmlEscape(in.options.run_dir.string()) << "</code></h2>"
         << TableHtml(t, "artifacts");
  }
  html << "</main>\n";
  html << "<script type=\"application/json\" id=\"ausbau-data\">" << in.data << "</script>\n";
  html << in.store.Html();
  html << "<script type=\"module\">\n" << ScriptSafe(in.assets.viewer) << "\n</script>\n</body>\n</html>\n";
  return html.str();
}

}  // namespace ausbau::report_internal
