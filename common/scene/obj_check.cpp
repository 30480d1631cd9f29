#include "scene/obj_check.h"

#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace ausbau {
namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t'; }
bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// The words of a line, split at blanks.
std::vector<std::string_view> Words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsBlank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !IsBlank(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool EqualsNoCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if ((a[i] | 0x20) != b[i]) return false;
  }
  return true;
}

// A number as assimp's fast_atof reads it: an optional sign, then digits
// with an optional fraction and exponent, or nan/inf/infinity. It must
// start with a digit after the sign (assimp counts a vertex's numbers by
// their first character, so ".5" is not counted and the vertex dropped),
// and its integer part has at most 18 digits (assimp reads a longer one as
// 0), its exponent at most 4 (beyond, it is 0 or infinite anyway), and the
// whole at most 64 characters (assimp copies a word into a fixed buffer and
// reads the rest of a longer one as the next number; a double needs 25).
bool IsObjNumber(std::string_view word) {
  if (word.size() > 64) return false;
  std::size_t i = 0;
  if (i < word.size() && (word[i] == '+' || word[i] == '-')) ++i;
  const std::string_view rest = word.substr(i);
  if (EqualsNoCase(rest, "nan") || EqualsNoCase(rest, "inf") || EqualsNoCase(rest, "infinity")) return true;
  const std::size_t integer_start = i;
  while (i < word.size() && IsDigit(word[i])) ++i;
  const std::size_t integer_digits = i - integer_start;
  if (integer_digits == 0 || integer_digits > 18) return false;
  if (i < word.size() && word[i] == '.') {
    ++i;
    while (i < word.size() && IsDigit(word[i])) ++i;
  }
  if (i < word.size() && (word[i] == 'e' || word[i] == 'E')) {
    ++i;
    if (i < word.size() && (word[i] == '+' || word[i] == '-')) ++i;
    const std::size_t exponent_start = i;
    while (i < word.size() && IsDigit(word[i])) ++i;
    if (i == exponent_start || i - exponent_start > 4) return false;
  }
  return i == word.size();
}

// An index as assimp's face parser reads it (atoi, then it skips as many
// characters as the value has digits): a nonzero int without '+' or
// leading zeros, else the skip and the text disagree.
bool ParseObjIndex(std::string_view text, long long* value) {
  std::size_t i = 0;
  const bool negative = !text.empty() && text[0] == '-';
  if (negative) ++i;
  if (i >= text.size() || text[i] < '1' || text[i] > '9' || text.size() - i > 10) return false;
  long long v = 0;
  for (; i < text.size(); ++i) {
    if (!IsDigit(text[i])) return false;
    v = v * 10 + (text[i] - '0');
  }
  if (v > 2147483647LL) return false;
  *value = negative ? -v : v;
  return true;
}

// What a face, line or point statement refers to, by kind: vertex,
// texture coordinate, normal.
constexpr int kKinds = 3;
constexpr const char* kKindNames[kKinds] = {"vertices", "texture coordinates", "normals"};
constexpr const char* kKindName[kKinds] = {"vertex", "texture coordinate", "normal"};

class ObjChecker {
 public:
  explicit ObjChecker(std::string name) : name_(std::move(name)) {}

  void Line(std::string_view line) {
    ++line_number_;
    if (line_number_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 byte order mark
    const std::string control = FirstControlCharacter(line);
    if (!control.empty()) Fail("a control character (" + control + ")");
    const std::size_t last = line.find_last_not_of(" \t");
    if (last != std::string_view::npos && line[last] == '\\') Fail("a line continuation ('\\' at the end of the line)");
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    const std::vector<std::string_view> words = Words(line);
    if (words.empty()) return;
    const std::string_view keyword = words[0];
    if (in_free_form_) {  // assimp skips a cstype section up to its "end"
      in_free_form_ = keyword != "end";
      return;
    }
    if (IsBlank(line[0])) Fail("a statement after leading blanks (assimp skips it)");
    if (keyword == "v") {
      Numbers(words, "a vertex", {3, 4, 6}, "3, 4 or 6");
      ++counts_[0];
    } else if (keyword == "vt") {
      Numbers(words, "a texture coordinate", {2, 3}, "2 or 3");
      ++counts_[1];
    } else if (keyword == "vn") {
      Numbers(words, "a normal", {3}, "3");
      ++counts_[2];
    } else if (keyword == "f" || keyword == "l" || keyword == "p") {
      References(words);
    } else if (keyword == "cstype") {
      in_free_form_ = true;
    } else if (keyword != "vp" && keyword != "g" && keyword != "o" &&
               std::string_view("vflpgo").find(keyword[0]) != std::string_view::npos) {
      // assimp picks the statement by the first character: "foo 1 2 3"
      // would be read as a face.
      Fail("unknown statement '" + Shown(keyword) + "'");
    }
  }

  // The positive references, checked once every element is counted (a
  // face may refer forward).
  void Finish() const {
    for (int k = 0; k < kKinds; ++k) {
      if (max_reference_[k] > counts_[k]) {
        throw InputErrorAt(name_, "malformed OBJ file (line " + std::to_string(max_reference_line_[k]) +
                                      ": refers to " + kKindName[k] + " " + std::to_string(max_reference_[k]) +
                                      ", out of range (the file has " + std::to_string(counts_[k]) + " " +
                                      kKindNames[k] + ")");
      }
    }
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputErrorAt(name_, "malformed OBJ file (line " + std::to_string(line_number_) + ": " + what + ")");
  }

  static std::string Shown(std::string_view word) {
    return word.size() <= 24 ? std::string(word) : std::string(word.substr(0, 24)) + "...";
  }

  void Numbers(const std::vector<std::string_view>& words, const char* what, std::initializer_list<std::size_t> allowed,
               const char* allowed_text) const {
    for (std::size_t k = 1; k < words.size(); ++k) {
      if (!IsObjNumber(words[k])) Fail("'" + Shown(words[k]) + "' in " + what + " is not a number assimp reads");
    }
    const std::size_t count = words.size() - 1;
    for (std::size_t a : allowed) {
      if (count == a) return;
    }
    Fail(std::string(what) + " of " + std::to_string(count) + " numbers (expected " + allowed_text + ")");
  }

  void References(const std::vector<std::string_view>& words) {
    if (words.size() < 2) Fail("'" + std::string(words[0]) + "' without vertices");
    int form = -1;  // bit k: kind k is given
    for (std::size_t w = 1; w < words.size(); ++w) {
      const std::string_view corner = words[w];
      std::string_view parts[kKinds];
      int given = 0, slashes = 0;
      std::size_t start = 0;
      for (std::size_t i = 0; i <= corner.size(); ++i) {
        if (i < corner.size() && corner[i] != '/') continue;
        if (slashes >= kKinds) Fail("'" + Shown(corner) + "' has more than two '/'");
        parts[slashes] = corner.substr(start, i - start);
        if (!parts[slashes].empty()) given |= 1 << slashes;
        ++slashes;
        start = i + 1;
      }
      // "v", "v/t", "v//n", "v/t/n"; "v/t/" and "v//" are none.
      const bool well_formed = (given & 1) && !(slashes == 3 && !(given & 4)) && !(slashes == 2 && !(given & 2));
      if (!well_formed) Fail("'" + Shown(corner) + "' is not v, v/t, v//n or v/t/n");
      if (words[0] == "p" && given != 1) Fail("a point '" + Shown(corner) + "' with more than a vertex");
      if (form >= 0 && given != form)
        Fail("corners of different forms ('" + Shown(words[1]) + "', '" + Shown(corner) + "')");
      form = given;
      for (int k = 0; k < kKinds; ++k) {
        if (!(given & (1 << k))) continue;
        long long index = 0;
        if (!ParseObjIndex(parts[k], &index)) {
          Fail("'" + Shown(parts[k]) + "' in '" + Shown(corner) +
               "' is not an index (a nonzero integer without '+' or leading zeros)");
        }
        if (index < 0 && -index > counts_[k]) {
          Fail("relative index " + std::to_string(index) + " in '" + Shown(corner) + "' reaches before the first of " +
               std::to_string(counts_[k]) + " " + kKindNames[k]);
        }
        if (index > max_reference_[k]) {
          max_reference_[k] = index;
          max_reference_line_[k] = line_number_;
        }
      }
    }
  }

  std::string name_;
  long long line_number_ = 0;
  bool in_free_form_ = false;
  long long counts_[kKinds] = {0, 0, 0};
  long long max_reference_[kKinds] = {0, 0, 0};
  long long max_reference_line_[kKinds] = {0, 0, 0};
};

}  // namespace

std::string FirstControlCharacter(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  for (char c : line) {
    const unsigned char u = static_cast<unsigned char>(c);
    if ((u < 0x20 && c != '\t') || u == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02X", u);
      return hex;
    }
  }
  return "";
}

void CheckObjStructure(const std::filesystem::path& path, const std::string& name) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputErrorAt(name, "cannot read mesh (cannot open file)");
  ObjChecker checker(name);
  std::string line;
  // assimp ends a line at '\n' or '\r': "\r\n" is one line end, a lone '\r'
  // (old Mac files) one too.
  while (std::getline(in, line)) {
    std::string_view rest(line);
    if (!rest.empty() && rest.back() == '\r') rest.remove_suffix(1);
    for (std::size_t cr; (cr = rest.find('\r')) != std::string_view::npos; rest.remove_prefix(cr + 1)) {
      checker.Line(rest.substr(0, cr));
    }
    checker.Line(rest);
  }
  checker.Finish();
}

}  // namespace ausbau
