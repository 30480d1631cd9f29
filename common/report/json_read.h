// A small JSON reader for the files a report shows (verdict.json): RFC 8259
// values into a tree. Numbers are doubles, strings are UTF-8 with \u escapes
// decoded (surrogate pairs joined); nesting is limited to 64 levels.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ausbau::report_internal {

struct JsonValue {
  enum class Type { kNull, kBool, kNumber, kString, kArray, kObject };
  Type type = Type::kNull;
  bool boolean = false;
  double number = 0;
  std::string string;
  std::vector<JsonValue> items;              // array
  std::map<std::string, JsonValue> members;  // object (a repeated key: the last one)

  // The member `key` of an object, or null (also for a non-object).
  const JsonValue* Find(const std::string& key) const;
  // A path of keys "a.b.c"; null where any step is missing.
  const JsonValue* At(const std::string& dotted) const;
  bool IsNumber() const { return type == Type::kNumber; }
  bool IsString() const { return type == Type::kString; }
  bool IsBool() const { return type == Type::kBool; }
};

// Parses `text`; on malformed input returns false and says why in `error`
// (with the byte offset).
bool ParseJson(const std::string& text, JsonValue* out, std::string* error);

}  // namespace ausbau::report_internal
