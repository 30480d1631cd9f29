#include "bench_report.h"

#include <fcl/config.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace ausbau::bench {

std::string SafeName(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_';
    out += keep ? c : '_';
  }
  return out;
}

namespace {

// A time or count with about three significant digits, without exponents.
std::string Num(double v) {
  if (!std::isfinite(v)) return "–";
  const double a = std::abs(v);
  if (a >= 100) return Fmt("%.0f", v);
  if (a >= 10) return Fmt("%.1f", v);
  if (a >= 1) return Fmt("%.2f", v);
  if (a >= 0.01 || a == 0) return Fmt("%.3f", v);
  return Fmt("%.4f", v);
}

std::string Percent(double fraction) { return Fmt("%.0f%%", 100.0 * fraction); }

const ConfigInfo* FindConfig(const SceneResult& scene, const std::string& label) {
  for (const ConfigInfo& c : scene.configs) {
    if (c.label == label && c.skipped.empty()) return &c;
  }
  return nullptr;
}

}  // namespace

Stats Summarize(const std::vector<RunRecord>& runs, const std::string& label, double time_limit_s) {
  Stats s;
  std::vector<double> times;
  double checks = 0;
  for (const RunRecord& r : runs) {
    if (r.label != label) continue;
    ++s.runs;
    if (r.success) ++s.successes;
    if (r.dense_check == 0) ++s.bad_paths;
    times.push_back(r.success ? std::min(r.time_s, time_limit_s) : time_limit_s);
    checks += static_cast<double>(r.collision_checks);
  }
  if (times.empty()) return s;
  std::sort(times.begin(), times.end());
  const std::size_t n = times.size();
  s.median_s = n % 2 ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
  double sum = 0;
  for (double t : times) sum += t;
  s.mean_s = sum / n;
  s.mean_checks = checks / n;
  return s;
}

ResultsCsv::ResultsCsv(const std::filesystem::path& path) : out_(path) {
  if (!out_) throw std::runtime_error("cannot write " + path.string());
  out_ << "scene,planner,seed,success,time_s,collision_checks,iterations,nodes,dense_check\n";
  out_.flush();
}

void ResultsCsv::Add(const RunRecord& r) {
  out_ << r.scene << ',' << r.label << ',' << r.seed << ',' << (r.success ? 1 : 0) << ',' << Fmt("%.6f", r.time_s)
       << ',' << r.collision_checks << ',' << r.iterations << ',' << r.nodes << ','
       << (r.dense_check < 0 ? ""
           : r.dense_check   ? "ok"
                             : "bad")
       << '\n';
  out_.flush();
}

namespace {

// The best OMPL configuration of a scene: lowest median, then lowest mean.
const ConfigInfo* OmplBest(const SceneResult& scene, double time_limit_s, Stats* best_stats) {
  const ConfigInfo* best = nullptr;
  for (const ConfigInfo& c : scene.configs) {
    if (!c.ompl || !c.skipped.empty()) continue;
    const Stats s = Summarize(scene.runs, c.label, time_limit_s);
    if (s.runs == 0) continue;
    if (!best || s.median_s < best_stats->median_s ||
        (s.median_s == best_stats->median_s && s.mean_s < best_stats->mean_s)) {
      best = &c;
      *best_stats = s;
    }
  }
  return best;
}

std::string Ratio(double a, double b) { return (b > 0 && std::isfinite(a)) ? Num(a / b) : "–"; }

std::string MetText(bool met) { return met ? "**met**" : "**not met**"; }

// The targets of the issue, checked on the scenes that were run.
std::string TargetsSection(const std::vector<SceneResult>& scenes, double time_limit_s) {
  std::ostringstream md;
  md << "## Targets\n\n";
  const std::string cr = "CR-RRTC";
  const std::string def = "Def-RRTC";
  auto find_scene = [&](const std::string& name) -> const SceneResult* {
    for (const SceneResult& s : scenes) {
      if (s.name == name && s.loaded) return &s;
    }
    return nullptr;
  };

  // 1. Success rate.
  {
    const std::vector<std::string> names = {"alpha-1.5", "Apartment", "Easy", "Home", "Twistycool"};
    std::vector<std::string> parts;
    bool all = true;
    int checked = 0;
    for (const std::string& name : names) {
      const SceneResult* s = find_scene(name);
      if (!s || !FindConfig(*s, cr)) {
        parts.push_back(name + " not run");
        continue;
      }
      const Stats st = Summarize(s->runs, cr, time_limit_s);
      ++checked;
      const bool ok = st.runs > 0 && st.success_rate() >= 0.95;
      all = all && ok;
      parts.push_back(name + " " + Percent(st.success_rate()) + (ok ? "" : " (below)"));
    }
    md << "1. CR-RRTC success >= 95% on alpha-1.5, Apartment, Easy, Home, Twistycool: ";
    md << (checked == 0 ? "**not checked**" : MetText(all) + (checked < 5 ? " on the scenes run" : "")) << " (";
    for (std::size_t i = 0; i < parts.size(); ++i) md << (i ? ", " : "") << parts[i];
    md << ").\n";
  }
  // 2. Against OMPL.
  {
    std::vector<std::string> parts;
    bool all = true;
    int checked = 0;
    for (const SceneResult& s : scenes) {
      if (!s.loaded || !FindConfig(s, cr) || !FindConfig(s, "OMPL default")) continue;
      const Stats st = Summarize(s.runs, cr, time_limit_s);
      const Stats od = Summarize(s.runs, "OMPL default", time_limit_s);
      Stats ob;
      const ConfigInfo* best = OmplBest(s, time_limit_s, &ob);
      if (st.runs == 0 || od.runs == 0 || !best) continue;
      ++checked;
      const bool tenth = st.median_s <= od.median_s / 10.0;
      const bool vs_best = st.median_s <= ob.median_s;
      all = all && tenth && vs_best;
      parts.push_back(s.name + ": " + Num(st.median_s) + " s vs OMPL default " + Num(od.median_s) +
                      " s (1/10: " + (tenth ? "yes" : "no") + "), OMPL best " + Num(ob.median_s) + " s [" +
                      best->label + "] (" + (vs_best ? "yes" : "no") + ")");
    }
    md << "2. CR-RRTC median <= 1/10 of OMPL default and <= OMPL best: "
       << (checked == 0 ? "**not checked**" : MetText(all)) << ".\n";
    for (const std::string& p : parts) md << "   - " << p << "\n";
  }
  // 3. Against Def-RRTC.
  {
    int faster = 0, compared = 0;
    std::vector<std::string> parts;
    for (const SceneResult& s : scenes) {
      if (!s.loaded || !FindConfig(s, cr) || !FindConfig(s, def)) continue;
      const Stats a = Summarize(s.runs, cr, time_limit_s);
      const Stats b = Summarize(s.runs, def, time_limit_s);
      if (a.runs == 0 || b.runs == 0) continue;
      ++compared;
      const bool f = a.median_s < b.median_s;
      if (f) ++faster;
      parts.push_back(s.name + " " + Num(a.median_s) + " vs " + Num(b.median_s) + " s" + (f ? "" : " (not faster)"));
    }
    md << "3. CR-RRTC faster than Def-RRTC (median) on the majority of scenes: "
       << (compared == 0 ? "**not checked**" : MetText(2 * faster > compared)) << " (" << faster << " of " << compared
       << ": ";
    for (std::size_t i = 0; i < parts.size(); ++i) md << (i ? ", " : "") << parts[i];
    md << ").\n";
  }
  // 4. alpha-1.2.
  {
    const SceneResult* s = find_scene("alpha-1.2");
    md << "4. alpha-1.2 CR-RRTC median < 10 s: ";
    if (!s || !FindConfig(*s, cr)) {
      md << "**not checked** (not run).\n";
    } else {
      const Stats st = Summarize(s->runs, cr, time_limit_s);
      md << MetText(st.runs > 0 && st.median_s < 10.0) << " (median " << Num(st.median_s) << " s, " << st.successes
         << "/" << st.runs << " solved"
         << (time_limit_s <= 10.0 ? "; the time limit is <= 10 s, so failures alone cannot push it above" : "")
         << ").\n";
    }
  }
  md << "\nMedians count failed runs as the time limit (" << Num(time_limit_s)
     << " s), so a median at the limit means at least half the runs failed.\n";
  return md.str();
}

}  // namespace

std::string WriteSummary(const std::filesystem::path& path, const MachineInfo& machine, const BenchSettings& settings,
                         const std::vector<SceneResult>& scenes) {
  std::ostringstream md;
  md << "# ausbau-bench: Ausbau planners side by side with OMPL's RRT-Connect\n\n";
  md << "- Machine: " << machine.cpu << ", " << machine.cores << " logical cores, " << Fmt("%.1f", machine.ram_gib)
     << " GiB RAM (host " << machine.host << ")\n";
  md << "- Software: " << machine.compiler << "; OMPL " << (machine.ompl.empty() ? "–" : machine.ompl) << "; FCL "
     << machine.fcl << "\n";
  md << "- Date: " << machine.date_utc << " (UTC); load average at start " << machine.load_start << ", at end "
     << LoadAverage() << "\n";
  md << "- Settings: " << settings.runs << " runs per planner and scene (Ausbau seeds " << settings.first_seed << ".."
     << settings.first_seed + settings.runs - 1 << ", OMPL RNG seeded once with " << settings.ompl_seed
     << "), time limit " << Num(settings.time_limit_s) << " s, one process, runs sequential and interleaved"
     << " (seed by seed), wall-clock time around the planner call. OMPL's runs draw from one seeded stream, so"
     << " they repeat for the same command line, not per seed\n";
  md << "- Edge checks: Ausbau " << Fmt("%g", settings.resolution * 100)
     << "% of D's diagonal per step; OMPL resolution mode `" << settings.ompl_resolution
     << "` (matched: OMPL's own validator with the fraction that keeps Ausbau's bound; exact: a validator"
     << " stepping like Ausbau's; see the scene lines)\n";
  md << "- Collision checks: calls of the same FCL checker object on both sides (out-of-bounds poses are"
     << " rejected before FCL and not counted)\n";
  md << "- Command: `" << settings.command_line << "`\n\n";

  for (const SceneResult& scene : scenes) {
    md << "## " << scene.name << "\n\n";
    for (const std::string& f : scene.facts) md << f << "\n";
    if (!scene.facts.empty()) md << "\n";
    if (!scene.loaded) {
      for (const std::string& n : scene.notes) md << "- " << n << "\n";
      md << "\n";
      continue;
    }
    const Stats od = Summarize(scene.runs, "OMPL default", settings.time_limit_s);
    Stats ob;
    const ConfigInfo* best = OmplBest(scene, settings.time_limit_s, &ob);
    md << "| planner | success | median time (s) | mean time (s) | mean collision checks | median / OMPL default"
       << " | median / OMPL best | bad paths |\n";
    md << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const ConfigInfo& c : scene.configs) {
      if (!c.skipped.empty()) {
        md << "| " << c.label << " | skipped | | | | | | |\n";
        continue;
      }
      const Stats s = Summarize(scene.runs, c.label, settings.time_limit_s);
      md << "| " << c.label << (best == &c ? " (best)" : "") << " | " << s.successes << "/" << s.runs << " ("
         << Percent(s.success_rate()) << ") | " << Num(s.median_s) << " | " << Num(s.mean_s) << " | "
         << Fmt("%.0f", s.mean_checks) << " | " << (od.runs ? Ratio(s.median_s, od.median_s) : "–") << " | "
         << (best ? Ratio(s.median_s, ob.median_s) : "–") << " | " << s.bad_paths << " |\n";
    }
    md << "\nFailed runs count as the time limit (" << Num(settings.time_limit_s)
       << " s) in the median and mean times; a ratio between medians at the time limit is only a bound.";
    if (best) md << " OMPL best = " << best->label << " (lowest median, " << Num(ob.median_s) << " s).";
    md << " \"bad paths\" = solved runs whose path failed the dense re-check (1% of D's diagonal).\n";
    std::vector<std::string> notes = scene.notes;
    for (const ConfigInfo& c : scene.configs) {
      if (!c.skipped.empty()) notes.push_back(c.label + " skipped: " + c.skipped);
      if (!c.error.empty()) notes.push_back(c.label + ": error during a run (counted as a failure): " + c.error);
    }
    if (!notes.empty()) {
      md << "\n";
      for (const std::string& n : notes) md << "- " << n << "\n";
    }
    md << "\n";
  }
  md << TargetsSection(scenes, settings.time_limit_s);
  const std::string text = md.str();
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
  return text;
}

void WriteOmplLog(const std::filesystem::path& path, const std::string& experiment, const MachineInfo& machine,
                  const BenchSettings& settings, const std::string& setup_text, const std::string& started_iso,
                  double total_s, const std::string& status_enum_line, const std::vector<LogPlanner>& planners) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  int max_runs = 0;
  for (const LogPlanner& p : planners) max_runs = std::max(max_runs, static_cast<int>(p.runs.size()));
  // Preamble.
  out << "OMPL version " << (machine.ompl.empty() ? "unknown" : machine.ompl) << "\n";
  out << "Experiment " << SafeName(experiment) << "\n";
  out << "Running on " << SafeName(machine.host) << "\n";
  out << "Starting at " << started_iso << "\n";
  out << "<<<|\n" << setup_text;
  if (!setup_text.empty() && setup_text.back() != '\n') out << "\n";
  out << "|>>>\n";
  out << "<<<|\n"
      << "CPU: " << machine.cpu << "\nlogical cores: " << machine.cores << "\nRAM: " << Fmt("%.1f", machine.ram_gib)
      << " GiB\ncompiler: " << machine.compiler << "\nFCL " << machine.fcl << "\n|>>>\n";
  out << settings.ompl_seed << " is the random seed\n";
  out << Fmt("%g", settings.time_limit_s) << " seconds per run\n";
  out << Fmt("%.0f", machine.ram_gib * 1024.0) << " MB per run\n";  // no limit of our own: the machine's RAM
  out << max_runs << " runs per planner\n";
  out << Fmt("%.3f", total_s) << " seconds spent to collect the data\n";
  out << "1 enum type\n" << status_enum_line << "\n";
  out << planners.size() << " planners\n";
  // Planners. Run properties in OMPL's order (sorted by name).
  for (const LogPlanner& p : planners) {
    out << p.name << "\n";
    const auto& common = p.config ? p.config->settings : std::vector<std::pair<std::string, std::string>>{};
    out << common.size() << " common properties\n";
    for (const auto& [key, value] : common) out << key << " = " << value << "\n";
    out << "8 properties for each run\n"
        << "collision_checks INTEGER\n"
        << "iterations INTEGER\n"
        << "nodes INTEGER\n"
        << "seed INTEGER\n"
        << "solved BOOLEAN\n"
        << "status ENUM\n"
        << "time REAL\n"
        << "verified BOOLEAN\n";
    out << p.runs.size() << " runs\n";
    for (const RunRecord* r : p.runs) {
      out << r->collision_checks << "; ";
      if (r->iterations > 0) out << r->iterations;
      out << "; " << r->nodes << "; " << r->seed << "; " << (r->success ? 1 : 0) << "; " << r->status << "; "
          << Fmt("%.6f", r->time_s) << "; ";
      if (r->dense_check >= 0) out << r->dense_check;
      out << "; \n";
    }
    out << ".\n";
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// ---- parameter study ----

const StudyCell* StudyResult::Best() const {
  const StudyCell* best = nullptr;
  for (const StudyCell& c : cells) {
    if (c.runs == 0) continue;
    if (!best || c.mean_pct < best->mean_pct || (c.mean_pct == best->mean_pct && c.successes > best->successes)) {
      best = &c;
    }
  }
  return best;
}

void WriteStudyCsv(const std::filesystem::path& path, const StudyResult& study) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  out << "u,range_max,runs,successes,success_rate,mean_time_s,mean_time_pct_of_tmax,mean_collision_checks\n";
  for (const StudyCell& c : study.cells) {
    out << Fmt("%.1f,%.1f,%d,%d,%.4f,%.6f,%.4f,%.1f\n", c.u, c.range_max, c.runs, c.successes,
               c.runs ? static_cast<double>(c.successes) / c.runs : 0.0, c.mean_time_s, c.mean_pct, c.mean_checks);
  }
}

namespace {

// Green (t = 0) over yellow to red (t = 1), as an SVG rgb() colour.
std::string HeatColour(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const double hue = 120.0 * (1.0 - t);  // HSL with s = 0.65, l = 0.55
  const double s = 0.65, l = 0.55;
  const double c = (1 - std::abs(2 * l - 1)) * s;
  const double hp = hue / 60.0;
  const double x = c * (1 - std::abs(std::fmod(hp, 2.0) - 1));
  double r = 0, g = 0, b = 0;
  if (hp < 1) {
    r = c;
    g = x;
  } else {
    r = x;
    g = c;
  }
  const double m = l - c / 2;
  auto to255 = [&](double v) { return static_cast<int>(std::lround(255 * (v + m))); };
  return Fmt("rgb(%d,%d,%d)", to255(r), to255(g), to255(b));
}

std::string XmlEscape(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

}  // namespace

void WriteStudySvg(const std::filesystem::path& path, const StudyResult& study) {
  const int rows = static_cast<int>(study.us.size());
  const int cols = static_cast<int>(study.ranges.size());
  const int cw = 62, ch = 36, left = 80, top = 112;
  const int grid_w = cols * cw, grid_h = rows * ch;
  const int legend_x = left + grid_w + 28;
  const int width = legend_x + 110, height = top + grid_h + 70;
  double lo = 1e300, hi = -1e300;
  for (const StudyCell& c : study.cells) {
    if (c.runs == 0) continue;
    lo = std::min(lo, c.mean_pct);
    hi = std::max(hi, c.mean_pct);
  }
  if (lo > hi) lo = hi = 0;
  auto scale = [&](double pct) { return hi > lo ? (pct - lo) / (hi - lo) : 0.0; };
  const StudyCell* best = study.Best();

  std::ostringstream svg;
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg << Fmt(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
      "font-family=\"DejaVu Sans, Arial, sans-serif\">\n",
      width, height, width, height);
  svg << Fmt("<rect x=\"0\" y=\"0\" width=\"%d\" height=\"%d\" fill=\"white\"/>\n", width, height);
  svg << Fmt("<text x=\"%d\" y=\"26\" font-size=\"17\" font-weight=\"bold\">%s: RRTC parameter study</text>\n", left,
             XmlEscape(study.scene).c_str());
  svg << Fmt(
      "<text x=\"%d\" y=\"46\" font-size=\"12\">mean time in %% of T_max = %g s (failures count as T_max), "
      "%d run%s per cell</text>\n",
      left, study.time_limit_s, study.runs, study.runs == 1 ? "" : "s");
  svg << Fmt(
      "<text x=\"%d\" y=\"62\" font-size=\"12\">green = fast, red = slow (scale %.1f%% .. %.1f%%); "
      "n/m = solved runs when not all; framed = best cell</text>\n",
      left, lo, hi);
  // Axis titles.
  svg << Fmt("<text x=\"%d\" y=\"%d\" font-size=\"14\" font-weight=\"bold\" text-anchor=\"middle\">range_max</text>\n",
             left + grid_w / 2, top - 24);
  svg << Fmt("<text x=\"24\" y=\"%d\" font-size=\"14\" font-weight=\"bold\" text-anchor=\"middle\">u</text>\n",
             top + grid_h / 2);
  for (int j = 0; j < cols; ++j) {
    svg << Fmt("<text x=\"%d\" y=\"%d\" font-size=\"12\" text-anchor=\"middle\">%.1f</text>\n", left + j * cw + cw / 2,
               top - 7, study.ranges[j]);
  }
  for (int i = 0; i < rows; ++i) {
    svg << Fmt("<text x=\"%d\" y=\"%d\" font-size=\"12\" text-anchor=\"end\">%.1f</text>\n", left - 8,
               top + i * ch + ch / 2 + 4, study.us[i]);
  }
  // Cells.
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const StudyCell& c = study.cells[i * cols + j];
      const int x = left + j * cw, y = top + i * ch;
      const std::string fill = c.runs ? HeatColour(scale(c.mean_pct)) : "rgb(220,220,220)";
      svg << Fmt(
          "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"%s\" stroke=\"white\" "
          "stroke-width=\"1\"/>\n",
          x, y, cw, ch, fill.c_str());
      if (c.runs == 0) continue;
      const bool all = c.successes == c.runs;
      svg << Fmt("<text x=\"%d\" y=\"%d\" font-size=\"12\" text-anchor=\"middle\"%s>%.1f</text>\n", x + cw / 2,
                 y + (all ? ch / 2 + 4 : ch / 2 - 1), (&c == best) ? " font-weight=\"bold\"" : "", c.mean_pct);
      if (!all) {
        svg << Fmt("<text x=\"%d\" y=\"%d\" font-size=\"9\" text-anchor=\"middle\">%d/%d</text>\n", x + cw / 2,
                   y + ch / 2 + 11, c.successes, c.runs);
      }
    }
  }
  if (best) {
    const int index = static_cast<int>(best - study.cells.data());
    const int i = index / cols, j = index % cols;
    svg << Fmt(
        "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"black\" "
        "stroke-width=\"3\"/>\n",
        left + j * cw + 1, top + i * ch + 1, cw - 2, ch - 2);
  }
  // Legend: a vertical colour bar from the minimum (top) to the maximum.
  svg << "<defs><linearGradient id=\"heat\" x1=\"0\" y1=\"0\" x2=\"0\" y2=\"1\">\n";
  for (int k = 0; k <= 8; ++k) {
    svg << Fmt("  <stop offset=\"%.3f\" stop-color=\"%s\"/>\n", k / 8.0, HeatColour(k / 8.0).c_str());
  }
  svg << "</linearGradient></defs>\n";
  svg << Fmt("<rect x=\"%d\" y=\"%d\" width=\"18\" height=\"%d\" fill=\"url(#heat)\" stroke=\"#444\"/>\n", legend_x,
             top, grid_h);
  svg << Fmt("<text x=\"%d\" y=\"%d\" font-size=\"11\">%.1f%% (fast)</text>\n", legend_x + 24, top + 10, lo);
  svg << Fmt("<text x=\"%d\" y=\"%d\" font-size=\"11\">%.1f%% (slow)</text>\n", legend_x + 24, top + grid_h, hi);
  if (best) {
    svg << Fmt(
        "<text x=\"%d\" y=\"%d\" font-size=\"12\">best: u = %.1f, range_max = %.1f: %.1f%% of T_max, "
        "%d/%d solved</text>\n",
        left, top + grid_h + 26, best->u, best->range_max, best->mean_pct, best->successes, best->runs);
  }
  svg << Fmt(
      "<text x=\"%d\" y=\"%d\" font-size=\"10\" fill=\"#555\">ausbau-bench --study; thesis 3.3.1, tables "
      "2-9</text>\n",
      left, top + grid_h + 46);
  svg << "</svg>\n";
  std::ofstream out(path);
  out << svg.str();
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string WriteStudySummary(const std::filesystem::path& path, const MachineInfo& machine,
                              const BenchSettings& settings, const std::vector<StudyResult>& studies) {
  std::ostringstream md;
  md << "# ausbau-bench --study: RRTC parameter study (thesis 3.3.1)\n\n";
  md << "- Machine: " << machine.cpu << ", " << machine.cores << " logical cores, " << Fmt("%.1f", machine.ram_gib)
     << " GiB RAM; " << machine.compiler << "; FCL " << machine.fcl << "\n";
  md << "- Date: " << machine.date_utc << " (UTC); load average at start " << machine.load_start << ", at end "
     << LoadAverage() << "\n";
  md << "- Grid: `rrtc` with fixed u (rows) and range_max (columns); " << settings.runs
     << (settings.runs == 1 ? " run" : " runs") << " per cell (seeds " << settings.first_seed << ".."
     << settings.first_seed + settings.runs - 1 << "), T_max = " << Num(settings.time_limit_s) << " s; edge resolution "
     << Fmt("%g", settings.resolution * 100) << "% of D's diagonal\n";
  md << "- Cell value: mean planning time in % of T_max, failed runs counted as T_max (as in the thesis's tables)\n";
  md << "- Command: `" << settings.command_line << "`\n\n";
  for (const StudyResult& study : studies) {
    md << "## " << study.scene << "\n\n";
    const StudyCell* best = study.Best();
    if (best) {
      md << "Best cell: **u = " << Fmt("%.1f", best->u) << ", range_max = " << Fmt("%.1f", best->range_max)
         << "**: " << Fmt("%.2f", best->mean_pct) << "% of T_max (mean " << Num(best->mean_time_s) << " s), "
         << best->successes << "/" << best->runs << " solved. Wall time of the grid: " << Num(study.wall_s)
         << " s. Files: `study-" << SafeName(study.scene) << ".csv`, `study-" << SafeName(study.scene) << ".svg`.\n\n";
    }
    md << "| u \\ range_max |";
    for (double r : study.ranges) md << " " << Fmt("%.1f", r) << " |";
    md << "\n|---|";
    for (std::size_t j = 0; j < study.ranges.size(); ++j) md << "---:|";
    md << "\n";
    for (std::size_t i = 0; i < study.us.size(); ++i) {
      md << "| " << Fmt("%.1f", study.us[i]) << " |";
      for (std::size_t j = 0; j < study.ranges.size(); ++j) {
        const StudyCell& c = study.cells[i * study.ranges.size() + j];
        std::string v = Fmt("%.1f", c.mean_pct);
        if (c.successes < c.runs) v += Fmt(" (%d/%d)", c.successes, c.runs);
        if (&c == best) v = "**" + v + "**";
        md << " " << v << " |";
      }
      md << "\n";
    }
    md << "\nValues in % of T_max = " << Num(study.time_limit_s)
       << " s; (n/m) = solved runs where not all were; bold = best.\n\n";
  }
  const std::string text = md.str();
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
  return text;
}

}  // namespace ausbau::bench
