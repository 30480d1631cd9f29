#include "report/report_headline.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <regex>

#include "core/format.h"
#include "report/report.h"
#include "report/report_util.h"

namespace ausbau::report_internal {

namespace {

double NumberAt(const JsonValue& v, const std::string& key) {
  const JsonValue* x = v.At(key);
  return x != nullptr && x->IsNumber() ? x->number : std::nan("");
}

std::string StringAt(const JsonValue& v, const std::string& key) {
  const JsonValue* x = v.At(key);
  return x != nullptr && x->IsString() ? x->string : "";
}

// The smallest clearance the verdict states, where it states one.
double VerdictClearance(const JsonValue& v) {
  for (const char* key : {"clearance.min", "clearance.minimum", "min_clearance", "clearance.min_clearance"}) {
    const double c = NumberAt(v, key);
    if (std::isfinite(c)) return c;
  }
  return std::nan("");
}

// "of 12 waypoints, 31.5 mm of travel and 0.25 rad (14.3°) of rotation":
// what is known of the path's size (empty where nothing is).
std::string PathSize(double waypoints, double translation, double rotation, const std::string& units) {
  std::vector<std::string> parts;
  if (std::isfinite(waypoints)) parts.push_back(Int(static_cast<std::int64_t>(waypoints)) + " waypoints");
  if (std::isfinite(translation)) parts.push_back(LengthText(translation, units) + " of travel");
  if (std::isfinite(rotation)) parts.push_back(AngleText(rotation) + " of rotation");
  std::string text;
  for (std::size_t i = 0; i < parts.size(); ++i)
    text += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  return text;
}

std::string RemovableWhy(const JsonValue& v, const PathEntry* shown, const std::string& units,
                         const ShellNamer& names) {
  std::string why = "D comes out of S along a path";
  const std::string size =
      PathSize(NumberAt(v, "path.waypoints"), NumberAt(v, "length.translation"), NumberAt(v, "length.rotation"), units);
  if (!size.empty()) why += " of " + size;
  const JsonValue* exact = v.Find("exact_check");
  if (exact != nullptr && exact->type == JsonValue::Type::kObject) {
    const double depth = NumberAt(*exact, "max_rigid_penetration");
    const double tolerance = NumberAt(*exact, "rigid_tolerance");
    const std::string allowed = std::isfinite(tolerance) ? " of the " + LengthText(tolerance, units) + " allowed" : "";
    if (!std::isfinite(depth)) {
      why += "; how deep its rigid part goes into S was not measured";
    } else if (depth > 0) {
      why += "; its rigid part penetrates S at most " + LengthText(depth, units) + allowed;
    } else {
      why += "; its rigid part stays clear of S (no contact" + (allowed.empty() ? "" : "," + allowed) + ")";
    }
    const std::string d = StringAt(*exact, "rigid_part"), sp = StringAt(*exact, "static_part");
    if (names && depth > 0 && d.rfind("shell ", 0) == 0 && sp.rfind("shell ", 0) == 0) {
      why += ", deepest where " + names(std::atoi(d.c_str() + 6), true) + " meets " +
             names(std::atoi(sp.c_str() + 6), false);
    }
    const double clips = NumberAt(*exact, "max_fastener_penetration");
    if (std::isfinite(clips) && clips > 0) why += ", while its clips bend through up to " + LengthText(clips, units);
  }
  const JsonValue* mliv = v.Find("max_labeled_mliv");
  if (mliv != nullptr && mliv->type == JsonValue::Type::kObject) {
    const double value = NumberAt(*mliv, "value"), waypoint = NumberAt(*mliv, "waypoint");
    why += "; the largest clip intersection (" + StringAt(*mliv, "measure") + ")";
    if (std::isfinite(value)) {
      why += " is " + VolumeText(value, units);
      if (std::isfinite(waypoint)) why += " at waypoint " + Int(static_cast<std::int64_t>(waypoint));
      const double tau = NumberAt(v, "tau");
      if (std::isfinite(tau)) why += " against tau " + VolumeText(tau, units);
    } else {
      why += " was not measured";
    }
  }
  double clearance = VerdictClearance(v);
  if (!std::isfinite(clearance) && shown != nullptr && !shown->at_samples.empty()) {
    // Away from the installed pose (where clips touch S by design): the
    // second half of the path.
    clearance = std::numeric_limits<double>::infinity();
    for (std::size_t k = shown->at_samples.size() / 2; k < shown->at_samples.size(); ++k)
      clearance = std::min(clearance, shown->at_samples[k].clearance);
    if (std::isfinite(clearance)) why += "; on its second half it keeps " + LengthText(clearance, units) + " from S";
  } else if (std::isfinite(clearance)) {
    why += "; its smallest clearance is " + LengthText(clearance, units);
  }
  return why + ".";
}

std::string NotRemovableWhy(const JsonValue& v, const std::string& units, const ShellNamer& names) {
  const JsonValue* exact = v.Find("exact_check");
  const JsonValue* blocks = v.Find("what_blocks");
  const std::string reason = exact != nullptr ? StringAt(*exact, "reason") : "";
  const JsonValue* valid = exact != nullptr ? exact->Find("valid") : nullptr;
  if (valid != nullptr && valid->IsBool() && !valid->boolean && !reason.empty()) {
    return "the path found fails the exact check: " +
           PlainVerdictText(names ? NameShells(reason, names) : reason, units) + ".";
  }
  std::string why = "no path out of S was found";
  const double seconds = NumberAt(v, "planner.seconds");
  if (std::isfinite(seconds)) why += " in " + Num(seconds) + " s of planning";
  const std::string summary = blocks != nullptr ? StringAt(*blocks, "summary") : "";
  if (!summary.empty()) why += "; " + PlainVerdictText(names ? NameShells(summary, names) : summary, units);
  return why + ".";
}

}  // namespace

std::string NameShells(const std::string& text, const ShellNamer& names) {
  // "shell 7 (convex, 12 triangles, centre [x, y, z], size a x b x c)":
  // the parentheses hold one level of brackets.
  static const std::regex kShell(R"(shell (\d+) \([^()\[\]]*(\[[^\]]*\][^()\[\]]*)*\))");
  std::string out;
  auto from = text.cbegin();
  for (std::sregex_iterator it(text.begin(), text.end(), kShell), end; it != end; ++it) {
    const auto& m = *it;
    const std::string after = text.substr(m.position() + m.length(), 5);
    out.append(from, m[0].first);
    out += names(std::stoi(m[1].str()), after != " of S");
    from = m[0].second;
  }
  out.append(from, text.cend());
  return out;
}

std::string PlainVerdictText(const std::string& text, const std::string& units) {
  // The verdict's texts (planning/exact_check.cpp) give lengths without a
  // unit and say an unmeasured depth as "inf": each rule below puts the unit
  // after a number in one known place, or says the missing value in words.
  const std::string unit = LengthUnit(units);
  static const std::string kNumber = R"(-?\d+(?:\.\d+)?(?:e[+-]?\d+)?)";
  struct Rule {
    std::regex pattern;
    std::string replacement;
  };
  const Rule rules[] = {
      // "after 8.916:" a straight pull's free distance
      {std::regex(R"((^|[^\w.])after ()" + kNumber + "):"), "$1after $2 " + unit + " of free travel:"},
      // "0.05 deep", "inf deep"
      {std::regex("(^|[ ,(])(?:inf|nan|-nan) deep"), "$1intersecting (depth not measured)"},
      {std::regex(R"((^|[^\w.])()" + kNumber + ") deep"), "$1$2 " + unit + " deep"},
      {std::regex(R"(\(tolerance ()" + kNumber + R"()\))"), "(tolerance $1 " + unit + ")"},
      // a shell described, not named: its centre and size
      {std::regex(R"(centre (\[[^\]]*\]))"), "centre $1 " + unit},
      {std::regex("size (" + kNumber + " x " + kNumber + " x " + kNumber + ")"), "size $1 " + unit},
      // any other non-finite number
      {std::regex(R"((^|[^A-Za-z])(?:-?inf|-?nan)(?![A-Za-z]))"), "$1not measured"},
  };
  std::string out = text;
  for (const Rule& rule : rules) out = std::regex_replace(out, rule.pattern, rule.replacement);
  // "on segment 8": the waypoints it joins, as the waypoint table numbers them
  static const std::regex kSegment(R"(on segment (\d+))");
  std::string said;
  auto from = out.cbegin();
  for (std::sregex_iterator it(out.begin(), out.end(), kSegment), end; it != end; ++it) {
    const int segment = std::stoi((*it)[1].str());
    said.append(from, (*it)[0].first);
    said += "between waypoint " + std::to_string(segment) + " and waypoint " + std::to_string(segment + 1);
    from = (*it)[0].second;
  }
  said.append(from, out.cend());
  return said;
}

Headline MakeHeadline(const JsonValue* verdict, const std::string& verdict_problem, const PathEntry* shown,
                      const std::string& units, const ShellNamer& names) {
  Headline h;
  // ausbau-verdict writes both "removable" (bool) and "status"; either says it.
  const JsonValue* removable = verdict != nullptr ? verdict->Find("removable") : nullptr;
  const JsonValue* status = verdict != nullptr ? verdict->Find("status") : nullptr;
  JsonValue from_status;
  if ((removable == nullptr || !removable->IsBool()) && status != nullptr && status->IsString() &&
      (status->string == "removable" || status->string == "not-removable")) {
    from_status.type = JsonValue::Type::kBool;
    from_status.boolean = status->string == "removable";
    removable = &from_status;
  }
  if (removable == nullptr || !removable->IsBool()) {
    h.verdict = "NO VERDICT";
    h.css = "none";
    h.sentence = verdict == nullptr ? verdict_problem : std::string("verdict.json has no 'removable'");
    if (shown == nullptr) {
      h.sentence += "; no path is shown.";
    } else {
      const std::string size = PathSize(static_cast<double>(shown->artifact.waypoints.size()),
                                        shown->length_translation ? *shown->length_translation : std::nan(""),
                                        shown->length_rotation ? *shown->length_rotation : std::nan(""), units);
      h.sentence += "; the " + shown->key + " path" + (size.empty() ? "" : " of " + size) + " " +
                    (shown->artifact.success ? "reaches its goal" : "does not reach its goal") +
                    " (not checked by ausbau-verdict).";
    }
    return h;
  }
  h.verdict = removable->boolean ? "REMOVABLE" : "NOT REMOVABLE";
  h.css = removable->boolean ? "ok" : "bad";
  h.sentence =
      removable->boolean ? RemovableWhy(*verdict, shown, units, names) : NotRemovableWhy(*verdict, units, names);
  return h;
}

std::string HeadlineHtml(const Headline& headline) {
  return "<section id=\"headline\" class=\"headline " + headline.css + "\"><span id=\"verdict-word\">" +
         HtmlEscape(headline.verdict) + "</span> <span id=\"verdict-why\">" + HtmlEscape(headline.sentence) +
         "</span></section>\n";
}

}  // namespace ausbau::report_internal
