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

std::string Length(double value, const std::string& units) { return Num(value) + (units.empty() ? "" : " " + units); }

// The smallest clearance the verdict states, where it states one.
double VerdictClearance(const JsonValue& v) {
  for (const char* key : {"clearance.min", "clearance.minimum", "min_clearance", "clearance.min_clearance"}) {
    const double c = NumberAt(v, key);
    if (std::isfinite(c)) return c;
  }
  return std::nan("");
}

std::string RemovableWhy(const JsonValue& v, const PathEntry* shown, const std::string& units,
                         const ShellNamer& names) {
  const double waypoints = NumberAt(v, "path.waypoints");
  std::string why = "D comes out of S along a path";
  if (std::isfinite(waypoints)) why += " of " + Int(static_cast<std::int64_t>(waypoints)) + " waypoints";
  const double translation = NumberAt(v, "length.translation"), rotation = NumberAt(v, "length.rotation");
  if (std::isfinite(translation)) why += " (" + Length(translation, units) + " of travel, " + Num(rotation) + " rad)";
  const JsonValue* exact = v.Find("exact_check");
  if (exact != nullptr && exact->type == JsonValue::Type::kObject) {
    const double depth = NumberAt(*exact, "max_rigid_penetration");
    why += "; its rigid part penetrates S at most " + Length(depth, units) + " of the " +
           Length(NumberAt(*exact, "rigid_tolerance"), units) + " allowed";
    const std::string d = StringAt(*exact, "rigid_part"), sp = StringAt(*exact, "static_part");
    if (names && depth > 0 && d.rfind("shell ", 0) == 0 && sp.rfind("shell ", 0) == 0) {
      why += ", deepest where " + names(std::atoi(d.c_str() + 6), true) + " meets " +
             names(std::atoi(sp.c_str() + 6), false);
    }
    const double clips = NumberAt(*exact, "max_fastener_penetration");
    if (std::isfinite(clips) && clips > 0) why += ", while its clips bend through up to " + Length(clips, units);
  }
  const JsonValue* mliv = v.Find("max_labeled_mliv");
  if (mliv != nullptr && mliv->type == JsonValue::Type::kObject) {
    why += "; the largest clip intersection (" + StringAt(*mliv, "measure") + ") is " + Num(NumberAt(*mliv, "value"));
    const double tau = NumberAt(v, "tau");
    if (std::isfinite(tau)) why += " against tau " + Num(tau);
  }
  double clearance = VerdictClearance(v);
  if (!std::isfinite(clearance) && shown != nullptr && !shown->at_samples.empty()) {
    // Away from the installed pose (where clips touch S by design): the
    // second half of the path.
    clearance = std::numeric_limits<double>::infinity();
    for (std::size_t k = shown->at_samples.size() / 2; k < shown->at_samples.size(); ++k)
      clearance = std::min(clearance, shown->at_samples[k].clearance);
    if (std::isfinite(clearance)) why += "; on its second half it keeps " + Length(clearance, units) + " from S";
  } else if (std::isfinite(clearance)) {
    why += "; its smallest clearance is " + Length(clearance, units);
  }
  return why + ".";
}

std::string NotRemovableWhy(const JsonValue& v, const ShellNamer& names) {
  const JsonValue* exact = v.Find("exact_check");
  const JsonValue* blocks = v.Find("what_blocks");
  const std::string reason = exact != nullptr ? StringAt(*exact, "reason") : "";
  const JsonValue* valid = exact != nullptr ? exact->Find("valid") : nullptr;
  if (valid != nullptr && valid->IsBool() && !valid->boolean && !reason.empty()) {
    return "the path found fails the exact check: " + (names ? NameShells(reason, names) : reason) + ".";
  }
  std::string why = "no path out of S was found";
  const double seconds = NumberAt(v, "planner.seconds");
  if (std::isfinite(seconds)) why += " in " + Num(seconds) + " s of planning";
  const std::string summary = blocks != nullptr ? StringAt(*blocks, "summary") : "";
  if (!summary.empty()) why += "; " + (names ? NameShells(summary, names) : summary);
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
    h.sentence = (verdict == nullptr ? verdict_problem : std::string("verdict.json has no 'removable'")) +
                 (shown == nullptr ? std::string("; no path is shown.")
                                   : "; the " + shown->key + " path " +
                                         (shown->artifact.success ? "reaches its goal" : "does not reach its goal") +
                                         " (not checked by ausbau-verdict).");
    return h;
  }
  h.verdict = removable->boolean ? "REMOVABLE" : "NOT REMOVABLE";
  h.css = removable->boolean ? "ok" : "bad";
  h.sentence = removable->boolean ? RemovableWhy(*verdict, shown, units, names) : NotRemovableWhy(*verdict, names);
  return h;
}

std::string HeadlineHtml(const Headline& headline) {
  return "<section id=\"headline\" class=\"headline " + headline.css + "\"><span id=\"verdict-word\">" +
         HtmlEscape(headline.verdict) + "</span> <span id=\"verdict-why\">" + HtmlEscape(headline.sentence) +
         "</span></section>\n";
}

}  // namespace ausbau::report_internal
