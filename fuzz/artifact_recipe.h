// Structure-aware fuzzing of our HDF5 artifact readers.
//
// Raw-byte mutation of an HDF5 file mostly exercises libhdf5's own parser
// (whose crashes on corrupt files we cannot fix), and almost never reaches
// our validation. Instead the fuzz input is a *recipe*: the harness reads it
// byte by byte and writes a real HDF5 file through the HDF5 API: which
// datasets and attributes exist, their types, ranks, dimensions (up to
// declared sizes of exabytes, never allocated) and values (NaN, +-inf,
// 1e300, extreme integers, raw bytes). Then the reader under test reads it.
// A recipe of zero bytes (or a recipe that runs out) yields the typical
// valid artifact described by the ArtifactSpec, so every mutation is a small
// step away from a file our reader accepts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ausbau::fuzz {

enum class Kind { kDouble, kFloat, kInt64, kUint8, kString };

struct DatasetSpec {
  std::string name;            // "stats/nodes": groups are created
  Kind kind = Kind::kDouble;   // the type our writer uses
  std::vector<long> dims;      // -1 = free (2 unless the recipe says otherwise); {} = scalar
  std::vector<double> values;  // the typical values, repeated cyclically
};

struct AttributeSpec {
  std::string object;  // "" = root
  std::string name;
  Kind kind = Kind::kString;  // kString, kDouble or kInt64
  std::string text;           // typical value of a string attribute
  double number = 0;          // typical value of a numeric attribute
};

struct ArtifactSpec {
  std::string schema;
  int version = 1;
  std::vector<DatasetSpec> datasets;
  std::vector<AttributeSpec> attributes;  // besides the root provenance attributes, which are always listed
};

// Writes the artifact the recipe describes (see artifact_recipe.cpp for the
// byte layout). Never throws; an object HDF5 refuses to create is left out.
void WriteRecipeArtifact(const ArtifactSpec& spec, const std::uint8_t* data, std::size_t size,
                         const std::filesystem::path& path);

}  // namespace ausbau::fuzz
