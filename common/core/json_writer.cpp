#include "core/json_writer.h"

#include <cmath>
#include <cstdio>

namespace ausbau {

std::string JsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buffer;
        } else {
          out += c;  // UTF-8 passes through unchanged
        }
    }
  }
  return out + "\"";
}

std::string JsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::string JsonVector(const Eigen::Vector3d& v) {
  return "[" + JsonNumber(v.x()) + ", " + JsonNumber(v.y()) + ", " + JsonNumber(v.z()) + "]";
}

std::string JsonQuaternion(const Eigen::Quaterniond& q) {
  return "[" + JsonNumber(q.w()) + ", " + JsonNumber(q.x()) + ", " + JsonNumber(q.y()) + ", " + JsonNumber(q.z()) + "]";
}

std::string JsonWriter::Text() const {
  const char* open = is_array_ ? "[" : "{";
  const char* close = is_array_ ? "]" : "}";
  if (members_.empty()) return std::string(open) + close;
  std::string out = std::string(open) + "\n";
  for (std::size_t i = 0; i < members_.size(); ++i) {
    out += "  ";
    if (!is_array_) out += JsonString(members_[i].first) + ": ";
    for (const char c : members_[i].second) {
      out += c;
      if (c == '\n') out += "  ";  // nested values get the parent's indentation
    }
    out += i + 1 < members_.size() ? ",\n" : "\n";
  }
  return out + close;
}

}  // namespace ausbau
