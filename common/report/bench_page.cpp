// The benchmark page (ausbau-report --bench-dir) and the Markdown subset it
// renders.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "report/report.h"
#include "report/report_util.h"

namespace ausbau {

using namespace report_internal;
namespace fs = std::filesystem;

// -------------------------------------------------------------- markdown

namespace {

std::string InlineMarkdown(const std::string& text) {
  std::string out;
  bool bold = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\\' && i + 1 < text.size() && std::strchr("\\`*_|#-", text[i + 1])) {
      out += HtmlEscape(std::string(1, text[++i]));
    } else if (c == '`') {
      const std::size_t end = text.find('`', i + 1);
      if (end == std::string::npos) {
        out += "`";
        continue;
      }
      out += "<code>" + HtmlEscape(text.substr(i + 1, end - i - 1)) + "</code>";
      i = end;
    } else if (c == '*' && i + 1 < text.size() && text[i + 1] == '*') {
      out += bold ? "</b>" : "<b>";
      bold = !bold;
      ++i;
    } else {
      out += HtmlEscape(std::string(1, c));
    }
  }
  if (bold) out += "</b>";
  return out;
}

// Splits "| a | b |" into cells, honouring "\|".
std::vector<std::string> TableCells(const std::string& line) {
  std::string s = Trim(line);
  if (!s.empty() && s.front() == '|') s.erase(0, 1);
  if (!s.empty() && s.back() == '|' && (s.size() < 2 || s[s.size() - 2] != '\\')) s.pop_back();
  std::vector<std::string> cells;
  std::string cell;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size() && s[i + 1] == '|') {
      cell += "\\|";
      ++i;
    } else if (s[i] == '|') {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += s[i];
    }
  }
  cells.push_back(Trim(cell));
  return cells;
}

bool IsAlignmentRow(const std::string& line) {
  const std::string s = Trim(line);
  if (s.empty() || s.find('-') == std::string::npos) return false;
  return s.find_first_not_of("|-: ") == std::string::npos;
}

// "- x" / "* x" / "1. x": the list kind ('u' or 'o'), the indent and the text.
bool ListItem(const std::string& line, char* kind, std::size_t* indent, std::string* text) {
  const std::size_t b = line.find_first_not_of(' ');
  if (b == std::string::npos) return false;
  if ((line[b] == '-' || line[b] == '*') && b + 1 < line.size() && line[b + 1] == ' ') {
    *kind = 'u';
    *indent = b;
    *text = line.substr(b + 2);
    return true;
  }
  std::size_t d = b;
  while (d < line.size() && std::isdigit(static_cast<unsigned char>(line[d]))) ++d;
  if (d > b && d + 1 < line.size() && line[d] == '.' && line[d + 1] == ' ') {
    *kind = 'o';
    *indent = b;
    *text = line.substr(d + 2);
    return true;
  }
  return false;
}

}  // namespace

std::string MarkdownToHtml(const std::string& markdown) {
  std::vector<std::string> lines;
  {
    std::istringstream in(markdown);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines.push_back(line);
    }
  }
  std::string out;
  std::size_t i = 0;
  while (i < lines.size()) {
    const std::string& line = lines[i];
    const std::string trimmed = Trim(line);
    char kind;
    std::size_t indent;
    std::string text;
    if (trimmed.empty()) {
      ++i;
    } else if (trimmed[0] == '#') {
      std::size_t level = trimmed.find_first_not_of('#');
      if (level == std::string::npos) level = trimmed.size();
      const std::size_t h = std::min<std::size_t>(level, 6);
      out += Fmt("<h%zu>", h) + InlineMarkdown(Trim(trimmed.substr(level))) + Fmt("</h%zu>\n", h);
      ++i;
    } else if (trimmed[0] == '|' && i + 1 < lines.size() && IsAlignmentRow(lines[i + 1])) {
      const std::vector<std::string> header = TableCells(line);
      const std::vector<std::string> align = TableCells(lines[i + 1]);
      auto style = [&](std::size_t c) -> std::string {
        if (c >= align.size()) return "";
        const std::string& a = align[c];
        if (a.size() > 1 && a.back() == ':' && a.front() == ':') return " style=\"text-align:center\"";
        if (!a.empty() && a.back() == ':') return " style=\"text-align:right\"";
        return "";
      };
      out += "<table><thead><tr>";
      for (std::size_t c = 0; c < header.size(); ++c)
        out += "<th" + style(c) + ">" + InlineMarkdown(header[c]) + "</th>";
      out += "</tr></thead><tbody>\n";
      i += 2;
      while (i < lines.size() && !Trim(lines[i]).empty() && Trim(lines[i])[0] == '|') {
        const std::vector<std::string> cells = TableCells(lines[i]);
        out += "<tr>";
        for (std::size_t c = 0; c < cells.size(); ++c)
          out += "<td" + style(c) + ">" + InlineMarkdown(cells[c]) + "</td>";
        out += "</tr>\n";
        ++i;
      }
      out += "</tbody></table>\n";
    } else if (ListItem(line, &kind, &indent, &text)) {
      // A list with nested items (deeper indent) as sub-lists.
      std::vector<std::pair<char, std::size_t>> open;  // kind, indent
      bool item_open = false;
      while (i < lines.size() && ListItem(lines[i], &kind, &indent, &text)) {
        while (!open.empty() && indent < open.back().second) {
          out += "</li>";
          out += open.back().first == 'u' ? "</ul>" : "</ol>";
          open.pop_back();
        }
        if (open.empty() || indent > open.back().second) {
          out += kind == 'u' ? "<ul>" : "<ol>";
          open.emplace_back(kind, indent);
          item_open = false;
        }
        if (item_open) out += "</li>\n";
        out += "<li>" + InlineMarkdown(text);
        item_open = true;
        ++i;
        // Continuation lines (indented, not a new item).
        while (i < lines.size() && !Trim(lines[i]).empty() && lines[i][0] == ' ' &&
               !ListItem(lines[i], &kind, &indent, &text)) {
          out += " " + InlineMarkdown(Trim(lines[i]));
          ++i;
        }
      }
      while (!open.empty()) {
        out += "</li>";
        out += open.back().first == 'u' ? "</ul>" : "</ol>";
        open.pop_back();
      }
      out += "\n";
    } else {
      std::string paragraph = InlineMarkdown(trimmed);
      ++i;
      while (i < lines.size() && !Trim(lines[i]).empty() && Trim(lines[i])[0] != '#' && Trim(lines[i])[0] != '|' &&
             !ListItem(lines[i], &kind, &indent, &text)) {
        paragraph += " " + InlineMarkdown(Trim(lines[i]));
        ++i;
      }
      out += "<p>" + paragraph + "</p>\n";
    }
  }
  return out;
}

// -------------------------------------------------------------- bench page

namespace {

struct BenchRow {
  std::string scene, planner;
  bool success = false;
  double time_s = 0;
};

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (char c : line) {
    if (c == ',') {
      cells.push_back(cell);
      cell.clear();
    } else if (c != '\r') {
      cell += c;
    }
  }
  cells.push_back(cell);
  return cells;
}

// results.csv of ausbau-bench: scene,planner,seed,success,time_s,...
std::vector<BenchRow> ReadResultsCsv(const fs::path& file, std::string* problem) {
  std::istringstream in(ReadTextFile(file));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = SplitCsvLine(line);
  auto column = [&](const char* name) -> int {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  const int scene = column("scene"), planner = column("planner"), success = column("success"), time = column("time_s");
  std::vector<BenchRow> rows;
  if (scene < 0 || planner < 0 || success < 0 || time < 0) {
    *problem = "expected the columns scene, planner, success, time_s";
    return rows;
  }
  while (std::getline(in, line)) {
    if (Trim(line).empty()) continue;
    const std::vector<std::string> cells = SplitCsvLine(line);
    if (cells.size() < header.size()) continue;
    BenchRow row;
    row.scene = cells[scene];
    row.planner = cells[planner];
    row.success = cells[success] == "1";
    try {
      row.time_s = std::stod(cells[time]);
    } catch (const std::exception&) {
      continue;
    }
    rows.push_back(row);
  }
  return rows;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string BarChartSvg(const std::string& scene, const std::vector<BenchRow>& rows) {
  std::vector<std::string> planners;
  for (const BenchRow& r : rows) {
    if (r.scene == scene && std::find(planners.begin(), planners.end(), r.planner) == planners.end()) {
      planners.push_back(r.planner);
    }
  }
  struct Bar {
    std::string planner;
    double median;
    int successes, runs;
  };
  std::vector<Bar> bars;
  double top = 0;
  for (const std::string& p : planners) {
    std::vector<double> times;
    int successes = 0;
    for (const BenchRow& r : rows) {
      if (r.scene != scene || r.planner != p) continue;
      times.push_back(r.time_s);
      successes += r.success;
    }
    bars.push_back({p, Median(times), successes, static_cast<int>(times.size())});
    top = std::max(top, bars.back().median);
  }
  const int label_w = 170, bar_w = 420, row_h = 24, width = label_w + bar_w + 190;
  const int height = 30 + row_h * static_cast<int>(bars.size()) + 10;
  std::string svg =
      Fmt("<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"bars\" width=\"%d\" height=\"%d\" "
          "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\" font-size=\"12\">",
          width, height, width, height);
  svg += Fmt("<text x=\"0\" y=\"16\" font-weight=\"bold\">%s: median time (s)</text>", HtmlEscape(scene).c_str());
  for (std::size_t k = 0; k < bars.size(); ++k) {
    const Bar& b = bars[k];
    const int y = 30 + static_cast<int>(k) * row_h;
    const double w = top > 0 ? bar_w * b.median / top : 0;
    const char* colour = b.successes == b.runs ? "#4c9a5b" : b.successes == 0 ? "#c8553d" : "#e0a030";
    svg += Fmt("<text x=\"%d\" y=\"%d\" text-anchor=\"end\">%s</text>", label_w - 8, y + 15,
               HtmlEscape(b.planner).c_str());
    svg +=
        Fmt("<rect x=\"%d\" y=\"%d\" width=\"%.1f\" height=\"%d\" fill=\"%s\"><title>%s: median %s s, %d/%d "
            "solved</title></rect>",
            label_w, y + 3, std::max(w, 1.0), row_h - 6, colour, HtmlEscape(b.planner).c_str(), Num(b.median).c_str(),
            b.successes, b.runs);
    svg += Fmt("<text x=\"%.1f\" y=\"%d\">%s s (%d/%d solved)</text>", label_w + std::max(w, 1.0) + 6, y + 15,
               Num(b.median).c_str(), b.successes, b.runs);
  }
  return svg + "</svg>";
}

}  // namespace

std::string BuildBenchPageHtml(const fs::path& bench_dir, ReportSummary* summary) {
  ReportSummary local;
  if (!summary) summary = &local;
  std::error_code ec;
  if (!fs::is_directory(bench_dir, ec)) throw InputErrorAt(bench_dir.string(), "benchmark folder not found");
  std::vector<fs::path> svgs;
  for (const auto& entry : fs::directory_iterator(bench_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("study-", 0) == 0 && entry.path().extension() == ".svg") svgs.push_back(entry.path());
  }
  std::sort(svgs.begin(), svgs.end());
  const fs::path summary_md = bench_dir / "summary.md", study_md = bench_dir / "study-summary.md",
                 results = bench_dir / "results.csv";
  if (!IsRegularFile(summary_md) && !IsRegularFile(study_md) && !IsRegularFile(results) && svgs.empty()) {
    throw InputErrorAt(bench_dir.string(),
                       "no benchmark outputs (summary.md, study-summary.md, results.csv or study-*.svg)");
  }
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<title>Ausbau benchmarks: " << HtmlEscape(bench_dir.string()) << "</title>\n<style>" << kStyle
       << "main h1 { font-size: 20px; } main h2 { font-size: 17px; border-bottom: 1px solid #d5dbe3; }"
          " svg { max-width: 100%; height: auto; display: block; margin: 6px 0 14px; }"
          "</style>\n</head>\n<body>\n<header><h1>Ausbau benchmarks</h1><p>from <code>"
       << HtmlEscape(bench_dir.string()) << "</code>, written by ausbau-report " << AUSBAU_VERSION
       << "</p></header>\n<main>\n";
  if (IsRegularFile(results)) {
    std::string problem;
    const std::vector<BenchRow> rows = ReadResultsCsv(results, &problem);
    html << "<section id=\"bars\"><h1>Median planning time per scene</h1>";
    if (!problem.empty()) {
      html << "<p class=\"note\">results.csv: " << HtmlEscape(problem) << "</p>";
      summary->notes.push_back(results.string() + ": " + problem);
    } else {
      html << "<p>From <code>results.csv</code> (" << rows.size()
           << " runs): the median over all runs, failed runs with their recorded time (about the time limit);"
              " green = all solved, amber = some, red = none.</p>";
      std::vector<std::string> scenes;
      for (const BenchRow& r : rows) {
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
      }
      for (const std::string& s : scenes) html << BarChartSvg(s, rows) << "\n";
    }
    html << "</section>\n";
    summary->used.push_back("results: " + results.string());
  }
  for (const fs::path& md : {summary_md, study_md}) {
    if (!IsRegularFile(md)) continue;
    html << "<section class=\"markdown\">" << MarkdownToHtml(ReadTextFile(md)) << "</section>\n";
    summary->used.push_back("markdown: " + md.string());
  }
  if (!svgs.empty()) html << "<section id=\"heatmaps\"><h1>Parameter study heat maps</h1>\n";
  for (const fs::path& svg_file : svgs) {
    std::string svg = ReadTextFile(svg_file);
    if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find("?>") + 2);
    const std::size_t at = svg.find("<svg");
    if (at == std::string::npos) {
      summary->notes.push_back(svg_file.string() + ": not an SVG, skipped");
      continue;
    }
    html << "<h2>" << HtmlEscape(svg_file.filename().string()) << "</h2>\n" << svg.substr(at) << "\n";
    summary->used.push_back("heat map: " + svg_file.string());
  }
  if (!svgs.empty()) html << "</section>\n";
  html << "</main>\n</body>\n</html>\n";
  return html.str();
}

}  // namespace ausbau
