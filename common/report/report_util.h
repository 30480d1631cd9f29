// Internal helpers of the report layer (not part of its interface): text
// files, the JSON written into the page, number formatting, binary buffers,
// HTML tables and the page's style. In their own namespace, so that they do
// not meet core/json_writer.h's JsonString (which escapes differently).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/pose.h"

namespace ausbau::report_internal {

std::string ReadTextFile(const std::filesystem::path& file);
bool IsRegularFile(const std::filesystem::path& file);
// A regular file that is not a symbolic link (lstat). The files a report
// takes from a run folder on its own (not named on the command line) must
// be this: a link there may point at any file the user can read, whose
// bytes would then be embedded in a page meant to be shared.
bool IsOwnRegularFile(const std::filesystem::path& file);
bool IsSymbolicLink(const std::filesystem::path& file);

// A JSON string literal that is also safe inside an HTML <script> element
// ("<" is escaped, so "</script>" cannot appear).
std::string JsonString(std::string_view text);
std::string JsonNumber(double value);  // %.17g; null where not finite
std::string JsonNumbers(const double* values, std::size_t n);
std::string JsonNumbers(const std::vector<double>& values);
std::string JsonVector(const Eigen::Vector3d& v);
std::string JsonPose(const Pose& pose);  // {"t": [...], "q": [w, x, y, z]}

std::string Num(double value);  // %.4g, "–" where not finite
// Values said with their unit. The callers say a missing (non-finite)
// value in words; these only format finite ones.
// The unit of lengths: the scene's `units`, or "scene units" where it names
// none (empty, unitless, none).
std::string LengthUnit(const std::string& units);
std::string LengthText(double value, const std::string& units);  // "0.5 mm"
std::string VolumeUnit(const std::string& units);                // "mm³", "cubic scene units"
std::string VolumeText(double value, const std::string& units);  // "7.18 mm³", "7.18 cubic scene units"
std::string AngleText(double radians);                           // "0.221 rad (12.7°)"
std::string Int(std::int64_t value);
std::string PoseText(const Pose& p);
std::string VectorText(const Eigen::Vector3d& v);
std::string Trim(const std::string& s);

// Little-endian bytes of float32 / uint32 arrays, whatever the host's order.
std::string Float32Bytes(const std::vector<float>& values);
std::string Uint32Bytes(const std::vector<std::uint32_t>& values);

// Buffers embedded as <script type="application/octet-stream"> elements.
class BufferStore {
 public:
  // Returns the JSON reference {"buffer": i, "type": ..., "count": n}.
  std::string Add(const std::string& bytes, const char* type, std::size_t count);
  std::string Html() const;

 private:
  std::vector<std::string> buffers_;
};

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // cells are HTML already
};
std::string TableHtml(const Table& table, const std::string& id);

// The CSS of both pages.
extern const char kStyle[];

// Makes inline module code safe inside <script> (it must not close it).
std::string ScriptSafe(std::string_view code);

}  // namespace ausbau::report_internal
