// The artifact layer: every stage reads and writes HDF5 files through it.
//
// An artifact is a plain HDF5 file (readable by h5dump and h5py) whose root
// group carries these attributes (see schemas/README.md):
//   schema            string, e.g. "ausbau-path"
//   schema_version    int64
//   producer          string, e.g. "ausbau-plan"
//   producer_version  string
//   parameters        string, the resolved options as YAML
//   inputs            string, YAML map role -> content hash of each input
//   provenance        string, hash over all of the above: the cache key
// Writes are atomic: data goes to a temporary file beside the target, which is
// renamed onto the target only by Commit(). Readers validate schema name and
// version, and each dataset's presence, type and shape, with an InputError
// naming the file on any mismatch.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ausbau {

struct Provenance {
  std::string producer;
  std::string producer_version;
  std::string parameters_yaml;
  std::vector<std::pair<std::string, std::string>> inputs;  // role -> content hash

  // Hash over producer, version, parameters and inputs (in this order).
  std::string Hash() const;
};

template <typename T>
struct Array {
  std::vector<T> data;  // row-major
  std::vector<std::size_t> dims;
};

class ArtifactWriter {
 public:
  ArtifactWriter(std::filesystem::path path, std::string schema, int schema_version, const Provenance& provenance);
  ~ArtifactWriter();  // removes the temporary file unless committed
  ArtifactWriter(const ArtifactWriter&) = delete;
  ArtifactWriter& operator=(const ArtifactWriter&) = delete;

  // Datasets at a path like "stats/iterations" (groups are created). dims
  // must multiply to data.size(). Large datasets (> 64 KiB) are chunked and
  // deflate-compressed.
  void WriteDoubles(const std::string& name, const std::vector<double>& data, const std::vector<std::size_t>& dims);
  void WriteFloats(const std::string& name, const std::vector<float>& data, const std::vector<std::size_t>& dims);
  void WriteInts(const std::string& name, const std::vector<std::int64_t>& data, const std::vector<std::size_t>& dims);
  void WriteBytes(const std::string& name, const std::vector<std::uint8_t>& data, const std::vector<std::size_t>& dims);
  // Attributes on the root ("") or on an existing dataset or group.
  void SetAttribute(const std::string& object, const std::string& name, const std::string& value);
  void SetAttribute(const std::string& object, const std::string& name, double value);
  void SetAttribute(const std::string& object, const std::string& name, std::int64_t value);

  // Flushes, closes and renames the temporary file onto the target.
  void Commit();

 private:
  struct Impl;
  Impl* impl_;
};

class ArtifactReader {
 public:
  // Throws InputError: missing file, not HDF5 (or truncated), wrong schema
  // name, unsupported version (anything but `schema_version`).
  ArtifactReader(std::filesystem::path path, const std::string& schema, int schema_version);
  ~ArtifactReader();
  ArtifactReader(const ArtifactReader&) = delete;
  ArtifactReader& operator=(const ArtifactReader&) = delete;

  const std::filesystem::path& path() const;
  std::string provenance_hash() const;
  std::string parameters_yaml() const;
  std::string producer() const;

  bool Has(const std::string& name) const;
  // expected_rank < 0: any rank. Throws InputError on a missing dataset, a
  // wrong rank, or a type that cannot be converted without loss.
  Array<double> ReadDoubles(const std::string& name, int expected_rank = -1) const;
  Array<float> ReadFloats(const std::string& name, int expected_rank = -1) const;
  Array<std::int64_t> ReadInts(const std::string& name, int expected_rank = -1) const;
  Array<std::uint8_t> ReadBytes(const std::string& name, int expected_rank = -1) const;
  std::string ReadStringAttribute(const std::string& object, const std::string& name) const;
  double ReadDoubleAttribute(const std::string& object, const std::string& name) const;
  std::int64_t ReadIntAttribute(const std::string& object, const std::string& name) const;

 private:
  struct Impl;
  Impl* impl_;
};

// The provenance hash of an existing artifact of this schema and version, or
// nothing when the file is missing, unreadable or of another schema/version.
// Stages use it to skip work: they reuse an output only when its hash equals
// the one they would produce, never because the file exists.
std::optional<std::string> ExistingProvenanceHash(const std::filesystem::path& path, const std::string& schema,
                                                  int schema_version);

}  // namespace ausbau
