#include "report/report_util.h"

#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "report/report.h"

namespace ausbau::report_internal {

namespace fs = std::filesystem;

std::string ReadTextFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputErrorAt(file.string(), "cannot read file");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool IsRegularFile(const fs::path& file) {
  std::error_code ec;
  return fs::is_regular_file(file, ec);
}

bool IsOwnRegularFile(const fs::path& file) {
  std::error_code ec;
  return fs::is_regular_file(fs::symlink_status(file, ec));
}

bool IsSymbolicLink(const fs::path& file) {
  std::error_code ec;
  return fs::is_symlink(fs::symlink_status(file, ec));
}

// A JSON string literal that is also safe inside an HTML <script> element
// ("<" is escaped, so "</script>" cannot appear).
std::string JsonString(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '<': out += "\\u003c"; break;
      case '>': out += "\\u003e"; break;
      case '&': out += "\\u0026"; break;
      default:
        if (u < 0x20) {
          out += Fmt("\\u%04x", u);
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string JsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  return Fmt("%.17g", value);
}

std::string JsonNumbers(const double* values, std::size_t n) {
  std::string out = "[";
  for (std::size_t i = 0; i < n; ++i) out += (i ? "," : "") + JsonNumber(values[i]);
  return out + "]";
}

std::string JsonNumbers(const std::vector<double>& values) { return JsonNumbers(values.data(), values.size()); }

std::string JsonVector(const Eigen::Vector3d& v) { return JsonNumbers(v.data(), 3); }

std::string JsonPose(const Pose& pose) {
  return "{\"t\":" + JsonVector(pose.t) + ",\"q\":[" + JsonNumber(pose.q.w()) + "," + JsonNumber(pose.q.x()) + "," +
         JsonNumber(pose.q.y()) + "," + JsonNumber(pose.q.z()) + "]}";
}

std::string Num(double value) {
  if (!std::isfinite(value)) return "–";
  return Fmt("%.4g", value);
}

std::string LengthUnit(const std::string& units) {
  std::string u;
  for (const char c : units) u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return u.empty() || u == "unitless" || u == "none" ? "scene units" : units;
}

std::string LengthText(double value, const std::string& units) { return Num(value) + " " + LengthUnit(units); }

std::string VolumeUnit(const std::string& units) {
  const std::string unit = LengthUnit(units);
  return unit == "scene units" ? "cubic scene units" : unit + "\u00b3";
}

std::string VolumeText(double value, const std::string& units) { return Num(value) + " " + VolumeUnit(units); }

std::string AngleText(double radians) { return Fmt("%.3g rad (%.3g\u00b0)", radians, radians * 180.0 / M_PI); }

std::string Int(std::int64_t value) { return std::to_string(value); }

std::string PoseText(const Pose& p) {
  return Fmt("t = [%.6g, %.6g, %.6g], q = [%.6g, %.6g, %.6g, %.6g]", p.t.x(), p.t.y(), p.t.z(), p.q.w(), p.q.x(),
             p.q.y(), p.q.z());
}

std::string VectorText(const Eigen::Vector3d& v) { return Fmt("[%.6g, %.6g, %.6g]", v.x(), v.y(), v.z()); }

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// Little-endian bytes of float32 / uint32 arrays, whatever the host's order.
std::string Float32Bytes(const std::vector<float>& values) {
  std::string bytes(values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, &values[i], 4);
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<char>((bits >> (8 * k)) & 0xff);
  }
  return bytes;
}

std::string Uint32Bytes(const std::vector<std::uint32_t>& values) {
  std::string bytes(values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<char>((values[i] >> (8 * k)) & 0xff);
  }
  return bytes;
}

std::string BufferStore::Add(const std::string& bytes, const char* type, std::size_t count) {
  buffers_.push_back(Base64Encode(bytes.data(), bytes.size()));
  return Fmt("{\"buffer\":%zu,\"type\":\"%s\",\"count\":%zu}", buffers_.size() - 1, type, count);
}

std::string BufferStore::Html() const {
  std::string out;
  for (std::size_t i = 0; i < buffers_.size(); ++i) {
    out += Fmt("<script type=\"application/octet-stream\" id=\"ausbau-buf-%zu\">", i);
    out += buffers_[i];
    out += "</script>\n";
  }
  return out;
}

std::string TableHtml(const Table& table, const std::string& id) {
  std::string out = "<table id=\"" + id + "\"><thead><tr>";
  for (const auto& h : table.header) out += "<th>" + h + "</th>";
  out += "</tr></thead><tbody>\n";
  for (const auto& row : table.rows) {
    out += "<tr>";
    for (std::size_t i = 0; i < row.size(); ++i)
      out += (i == 0 ? "<th>" : "<td>") + row[i] + (i == 0 ? "</th>" : "</td>");
    out += "</tr>\n";
  }
  return out + "</tbody></table>\n";
}

const char kStyle[] = R"CSS(
* { box-sizing: border-box; }
body { margin: 0; font: 14px/1.4 system-ui, -apple-system, "Segoe UI", sans-serif; color: #1d232b; background: #fafbfc; }
header { padding: 10px 18px; background: #24303e; color: #f2f4f7; }
header h1 { margin: 0; font-size: 19px; font-weight: 600; }
header p { margin: 2px 0 0; font-size: 12px; color: #b8c2cf; }
main { padding: 12px 18px 30px; max-width: 1500px; }
#view { position: relative; height: 62vh; min-height: 320px; background: #eef1f5; border: 1px solid #cfd6df; border-radius: 4px; overflow: hidden; }
#canvas3d { display: block; width: 100%; height: 100%; }
#view.nowebgl { height: auto; min-height: 0; padding: 14px 12px 30px; }
#view.nowebgl #canvas3d, #view.nowebgl #status, #view.nowebgl #viewhelp { display: none; }
#nowebgl { margin: 0; font-size: 15px; color: #7a4b00; }
#status { position: absolute; left: 10px; top: 8px; font-size: 12px; color: #3c4855; background: rgba(255,255,255,.75); padding: 2px 6px; border-radius: 3px; }
#legend { position: absolute; right: 10px; top: 8px; font-size: 12px; background: rgba(255,255,255,.85); padding: 4px 8px; border-radius: 3px; display: none; }
#legend .bar { width: 160px; height: 10px; margin: 3px 0; }
#help { position: absolute; left: 10px; bottom: 6px; font-size: 11px; color: #5b6773; }
#controls { display: flex; flex-wrap: wrap; gap: 8px 14px; align-items: center; padding: 8px 0; }
#controls button { min-width: 70px; padding: 4px 10px; font-size: 14px; }
#scrubber { flex: 1 1 320px; }
#controls label { font-size: 13px; white-space: nowrap; }
/* One width whatever the text says: the scrubber beside it must not move under the pointer. */
#timeinfo { font-variant-numeric: tabular-nums; font-size: 13px; flex: 0 0 50ch; white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
#plotbox { position: relative; border: 1px solid #cfd6df; border-radius: 4px; background: #fff; }
#plot { display: block; width: 100%; height: 190px; cursor: crosshair; }
#plotnote { font-size: 12px; color: #5b6773; margin: 4px 0 0; }
h2 { font-size: 16px; margin: 22px 0 8px; }
table { border-collapse: collapse; margin: 4px 0 10px; font-size: 13px; background: #fff; max-width: 100%; }
th, td { border: 1px solid #d5dbe3; padding: 3px 9px; text-align: left; vertical-align: top; overflow-wrap: anywhere; }
thead th { background: #eef1f5; }
tbody th { font-weight: 500; background: #f7f8fa; }
td { font-variant-numeric: tabular-nums; }
code { font-size: 12px; overflow-wrap: anywhere; }
h2 { overflow-wrap: anywhere; }
.tablebox { max-width: 100%; overflow-x: auto; }
.tablebox tbody th { overflow-wrap: normal; white-space: nowrap; }
.note { color: #7a4b00; }
.grid { display: flex; flex-wrap: wrap; gap: 0 28px; }
.grid > div { min-width: 0; max-width: 100%; }
.headline { margin: 4px 0 12px; padding: 10px 14px; border-radius: 4px; font-size: 16px; border: 1px solid #cfd6df; background: #fff; }
.headline #verdict-word { font-weight: 700; font-size: 19px; margin-right: 6px; }
.headline.ok { border-color: #4c9a5b; background: #eef7f0; } .headline.ok #verdict-word { color: #2d7a3e; }
.headline.bad { border-color: #c8553d; background: #fbefec; } .headline.bad #verdict-word { color: #b0361f; }
.headline.none #verdict-word { color: #5b6773; }
#plots { border: 1px solid #cfd6df; border-radius: 4px; background: #fff; }
canvas.plot { display: block; width: 100%; cursor: crosshair; border-bottom: 1px solid #eef1f5; }
#measureinfo { position: absolute; left: 10px; top: 32px; font-size: 12px; background: rgba(255,255,255,.9); padding: 2px 6px; border-radius: 3px; color: #8a1446; display: none; }
#section-info { font-variant-numeric: tabular-nums; }
#status, #legend, #help, #measureinfo { pointer-events: none; }
#waypointbox { max-height: 420px; overflow: auto; border: 1px solid #d5dbe3; }
#waypoints { margin: 0; font-size: 12px; max-width: none; }
#waypoints th, #waypoints td { overflow-wrap: normal; }
#waypoints thead th { position: sticky; top: 0; }
#waypoints tbody tr { cursor: pointer; }
#waypoints tbody tr:hover { background: #eef4fb; }
#waypoints tr.contact td { background: #fdf3e6; }
.explain { font-size: 12px; color: #5b6773; margin: 2px 0 6px; }
#downloads a { font-weight: 500; }
)CSS";

// Makes inline module code safe inside <script> (it must not close it).
std::string ScriptSafe(std::string_view code) {
  std::string out(code);
  for (std::size_t at = 0; (at = out.find("</script", at)) != std::string::npos; at += 2) out.replace(at, 2, "<\\/");
  return out;
}

}  // namespace ausbau::report_internal
