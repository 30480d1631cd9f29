// A small JSON writer for the files the tools write (verdict.json,
// ausbau-scene-check --json): objects and arrays built member by member,
// one member per line, two spaces of indentation per level, numbers with 10
// significant digits (%.10g) and non-finite numbers as null.
//
// Why not nlohmann-json (Debian's nlohmann-json3-dev): it prints doubles in
// their shortest round-trip form (6 as "6.0", 0.1 + 0.2 as
// "0.30000000000000004"), which would change every verdict.json that tools
// and the golden tests compare; the writer is 60 lines.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

namespace ausbau {

std::string JsonString(const std::string& text);  // quoted and escaped; UTF-8 passes through
std::string JsonNumber(double value);             // %.10g, or null where not finite
inline std::string JsonBool(bool value) { return value ? "true" : "false"; }
std::string JsonVector(const Eigen::Vector3d& v);         // [x, y, z]
std::string JsonQuaternion(const Eigen::Quaterniond& q);  // [w, x, y, z]

// An object (or array) whose nested values are passed as their text and
// indented with the parent.
class JsonWriter {
 public:
  explicit JsonWriter(bool is_array = false) : is_array_(is_array) {}
  JsonWriter& Add(const std::string& key, const std::string& raw_value) {
    members_.emplace_back(key, raw_value);
    return *this;
  }
  JsonWriter& Append(const std::string& raw_value) { return Add("", raw_value); }  // arrays
  JsonWriter& String(const std::string& key, const std::string& value) { return Add(key, JsonString(value)); }
  JsonWriter& Number(const std::string& key, double value) { return Add(key, JsonNumber(value)); }
  JsonWriter& Int(const std::string& key, long long value) { return Add(key, std::to_string(value)); }
  JsonWriter& Bool(const std::string& key, bool value) { return Add(key, JsonBool(value)); }
  JsonWriter& Null(const std::string& key) { return Add(key, "null"); }
  std::string Text() const;

 private:
  bool is_array_;
  std::vector<std::pair<std::string, std::string>> members_;
};

}  // namespace ausbau
