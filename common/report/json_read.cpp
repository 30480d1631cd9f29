#include "report/json_read.h"

#include <cstdlib>
#include <stdexcept>

namespace ausbau::report_internal {
namespace {

class Parser {
 public:
  explicit Parser(const std::string& text) : text_(text) {}

  JsonValue Document() {
    JsonValue v = Value(0);
    Space();
    if (at_ != text_.size()) Fail("text after the value");
    return v;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw std::runtime_error(what + " at byte " + std::to_string(at_));
  }
  void Space() {
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t' || text_[at_] == '\n' || text_[at_] == '\r'))
      ++at_;
  }
  bool Eat(const char* word) {
    const std::string w(word);
    if (text_.compare(at_, w.size(), w) != 0) return false;
    at_ += w.size();
    return true;
  }

  JsonValue Value(int depth) {
    if (depth > 64) Fail("nesting deeper than 64 levels");
    Space();
    if (at_ >= text_.size()) Fail("unexpected end");
    JsonValue v;
    const char c = text_[at_];
    if (c == '{') return Object(depth);
    if (c == '[') return Array(depth);
    if (c == '"') {
      v.type = JsonValue::Type::kString;
      v.string = String();
    } else if (Eat("true")) {
      v.type = JsonValue::Type::kBool;
      v.boolean = true;
    } else if (Eat("false")) {
      v.type = JsonValue::Type::kBool;
    } else if (Eat("null")) {
      v.type = JsonValue::Type::kNull;
    } else {
      v.type = JsonValue::Type::kNumber;
      v.number = Number();
    }
    return v;
  }

  JsonValue Object(int depth) {
    JsonValue v;
    v.type = JsonValue::Type::kObject;
    ++at_;  // {
    Space();
    if (at_ < text_.size() && text_[at_] == '}') return ++at_, v;
    for (;;) {
      Space();
      if (at_ >= text_.size() || text_[at_] != '"') Fail("expected a key");
      const std::string key = String();
      Space();
      if (at_ >= text_.size() || text_[at_] != ':') Fail("expected ':'");
      ++at_;
      v.members[key] = Value(depth + 1);
      Space();
      if (at_ < text_.size() && text_[at_] == ',') {
        ++at_;
      } else if (at_ < text_.size() && text_[at_] == '}') {
        ++at_;
        return v;
      } else {
        Fail("expected ',' or '}'");
      }
    }
  }

  JsonValue Array(int depth) {
    JsonValue v;
    v.type = JsonValue::Type::kArray;
    ++at_;  // [
    Space();
    if (at_ < text_.size() && text_[at_] == ']') return ++at_, v;
    for (;;) {
      v.items.push_back(Value(depth + 1));
      Space();
      if (at_ < text_.size() && text_[at_] == ',') {
        ++at_;
      } else if (at_ < text_.size() && text_[at_] == ']') {
        ++at_;
        return v;
      } else {
        Fail("expected ',' or ']'");
      }
    }
  }

  double Number() {
    const std::size_t start = at_;
    if (at_ < text_.size() && text_[at_] == '-') ++at_;
    auto digits = [&] {
      const std::size_t from = at_;
      while (at_ < text_.size() && text_[at_] >= '0' && text_[at_] <= '9') ++at_;
      return at_ > from;
    };
    if (!digits()) Fail("expected a value");
    if (at_ < text_.size() && text_[at_] == '.' && (++at_, !digits())) Fail("expected digits after '.'");
    if (at_ < text_.size() && (text_[at_] == 'e' || text_[at_] == 'E')) {
      ++at_;
      if (at_ < text_.size() && (text_[at_] == '+' || text_[at_] == '-')) ++at_;
      if (!digits()) Fail("expected an exponent");
    }
    return std::strtod(text_.substr(start, at_ - start).c_str(), nullptr);
  }

  unsigned Hex4() {
    if (at_ + 4 > text_.size()) Fail("short \\u escape");
    unsigned code = 0;
    for (int k = 0; k < 4; ++k) {
      const char h = text_[at_++];
      code <<= 4;
      if (h >= '0' && h <= '9')
        code |= h - '0';
      else if (h >= 'a' && h <= 'f')
        code |= h - 'a' + 10;
      else if (h >= 'A' && h <= 'F')
        code |= h - 'A' + 10;
      else
        Fail("bad \\u escape");
    }
    return code;
  }

  static void Utf8(unsigned code, std::string* out) {
    if (code < 0x80) {
      *out += static_cast<char>(code);
    } else if (code < 0x800) {
      *out += static_cast<char>(0xc0 | (code >> 6));
      *out += static_cast<char>(0x80 | (code & 0x3f));
    } else if (code < 0x10000) {
      *out += static_cast<char>(0xe0 | (code >> 12));
      *out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
      *out += static_cast<char>(0x80 | (code & 0x3f));
    } else {
      *out += static_cast<char>(0xf0 | (code >> 18));
      *out += static_cast<char>(0x80 | ((code >> 12) & 0x3f));
      *out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
      *out += static_cast<char>(0x80 | (code & 0x3f));
    }
  }

  std::string String() {
    ++at_;  // "
    std::string out;
    for (;;) {
      if (at_ >= text_.size()) Fail("unterminated string");
      const char c = text_[at_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) Fail("control character in a string");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (at_ >= text_.size()) Fail("unterminated string");
      const char e = text_[at_++];
      switch (e) {
        case '"':
        case '\\':
        case '/': out += e; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          unsigned code = Hex4();
          if (code >= 0xd800 && code < 0xdc00 && Eat("\\u")) {
            const unsigned low = Hex4();
            if (low >= 0xdc00 && low < 0xe000) code = 0x10000 + ((code - 0xd800) << 10) + (low - 0xdc00);
          }
          Utf8(code, &out);
          break;
        }
        default: Fail("bad escape");
      }
    }
  }

  const std::string& text_;
  std::size_t at_ = 0;
};

}  // namespace

const JsonValue* JsonValue::Find(const std::string& key) const {
  if (type != Type::kObject) return nullptr;
  const auto it = members.find(key);
  return it == members.end() ? nullptr : &it->second;
}

const JsonValue* JsonValue::At(const std::string& dotted) const {
  const JsonValue* v = this;
  std::size_t from = 0;
  while (v != nullptr) {
    const std::size_t dot = dotted.find('.', from);
    v = v->Find(dotted.substr(from, dot == std::string::npos ? std::string::npos : dot - from));
    if (dot == std::string::npos) break;
    from = dot + 1;
  }
  return v;
}

bool ParseJson(const std::string& text, JsonValue* out, std::string* error) {
  try {
    *out = Parser(text).Document();
    return true;
  } catch (const std::runtime_error& e) {
    if (error != nullptr) *error = e.what();
    return false;
  }
}

}  // namespace ausbau::report_internal
