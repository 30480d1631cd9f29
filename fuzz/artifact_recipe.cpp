// The recipe interpreter (see artifact_recipe.h).
//
// Byte layout, read front to back; a missing byte reads as 0, the typical
// choice. For each dataset of the spec, in order:
//   mode byte (mod 8): 0 typical; 1 absent; 2 another stored type (next
//     byte); 3 another rank (next byte, 0-4) with dims from the next bytes;
//     4 a huge declared size (chunked, never written: the file stays small);
//     5 typical type and rank, free dims from the next bytes (0-16);
//     6 a group instead of a dataset; 7 an H5S_NULL dataspace.
//   then one byte per element (up to 4096 elements) choosing its value
//   from a palette: the typical value, 0, 1, -1, NaN, +-inf, +-1e300,
//   the extreme integers, a byte value, 8 raw bytes, ...
// Then, for each attribute (the root provenance attributes first):
//   mode byte (mod 6): 0 typical; 1 absent; 2 the wrong kind; 3 a value
//   from the palette (a string from the next bytes: length, then text);
//   4 another representation (variable-length string, int32, float32);
//   5 two elements instead of one.
#include "artifact_recipe.h"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ausbau::fuzz {
namespace {

class Recipe {
 public:
  Recipe(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t Byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint64_t U64() {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = (v << 8) | Byte();
    return v;
  }
  std::string Text() {
    const std::size_t length = Byte() % 48;
    std::string s;
    for (std::size_t i = 0; i < length; ++i) s.push_back(static_cast<char>(Byte()));
    return s;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

struct Value {
  double d;
  std::int64_t i;
};

// The palette: index 0 is the typical value.
Value PaletteValue(Recipe& r, double typical) {
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
  const std::int64_t typical_int = std::isfinite(typical) ? static_cast<std::int64_t>(typical) : 0;
  switch (r.Byte() % 20) {
    case 1: return {0.0, 0};
    case 2: return {1.0, 1};
    case 3: return {-1.0, -1};
    case 4: return {kNan, kMin};
    case 5: return {kInf, kMax};
    case 6: return {-kInf, kMin + 1};
    case 7: return {1e300, std::int64_t{1} << 40};
    case 8: return {-1e300, -(std::int64_t{1} << 40)};
    case 9: return {9.3e18, kMax - 1};
    case 10: return {1e-300, std::int64_t{1} << 31};
    case 11: {
      const std::uint8_t b = r.Byte();
      return {static_cast<double>(b), static_cast<std::int64_t>(b)};
    }
    case 12: {
      const std::uint64_t bits = r.U64();
      double d;
      std::memcpy(&d, &bits, sizeof d);
      return {d, static_cast<std::int64_t>(bits)};
    }
    case 13: return {2.0, 2};
    case 14: return {typical + 1e-3, typical_int + 1};
    case 15: return {-typical, -typical_int};
    case 16: return {7.0, 7};
    case 17: return {std::numeric_limits<double>::denorm_min(), std::int64_t{1} << 62};
    default: return {typical, typical_int};
  }
}

struct StoredType {
  hid_t type;  // a predefined HDF5 type (or -1 for a 4-byte string)
  bool is_float;
};

StoredType TypeOf(Kind kind) {
  switch (kind) {
    case Kind::kDouble: return {H5T_IEEE_F64LE, true};
    case Kind::kFloat: return {H5T_IEEE_F32LE, true};
    case Kind::kInt64: return {H5T_STD_I64LE, false};
    case Kind::kUint8: return {H5T_STD_U8LE, false};
    case Kind::kString: return {-1, false};
  }
  return {H5T_IEEE_F64LE, true};
}

StoredType OtherType(std::uint8_t choice) {
  static const StoredType kTypes[] = {
      {H5T_IEEE_F64LE, true},
      {H5T_IEEE_F32LE, true},
      {H5T_STD_I64LE, false},
      {H5T_STD_U8LE, false},
      {H5T_STD_I32LE, false},
      {H5T_STD_I8LE, false},
      {H5T_STD_U64LE, false},
      {H5T_STD_U16LE, false},
      {H5T_IEEE_F64BE, true},
      {H5T_STD_U32BE, false},
      {-1, false},
  };
  return kTypes[choice % (sizeof kTypes / sizeof kTypes[0])];
}

// An HDF5 id closed at scope exit.
struct Id {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Id() {
    if (id >= 0) close(id);
  }
};

hid_t StringType(std::size_t length) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, length == 0 ? 1 : length);
  H5Tset_strpad(type, H5T_STR_NULLPAD);
  return type;
}

void WriteDataset(hid_t file, hid_t lcpl, hid_t dxpl, const DatasetSpec& spec, Recipe& r) {
  const std::uint8_t mode = r.Byte() % 8;
  if (mode == 1) return;
  if (mode == 6) {
    Id group{H5Gcreate2(file, spec.name.c_str(), lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    return;
  }
  StoredType stored = TypeOf(spec.kind);
  if (mode == 2) stored = OtherType(r.Byte());

  std::vector<hsize_t> dims;
  for (long d : spec.dims) dims.push_back(d >= 0 ? static_cast<hsize_t>(d) : 2);
  if (mode == 3) {
    dims.assign(r.Byte() % 5, 0);
    for (hsize_t& d : dims) d = r.Byte() % 17;
  } else if (mode == 5) {
    for (std::size_t k = 0; k < dims.size(); ++k) {
      if (spec.dims[k] < 0) dims[k] = r.Byte() % 17;
    }
  }
  Id dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  bool write_values = true;
  if (mode == 4) {
    // Sizes a small file can declare: 2^40 elements; a row count whose
    // product with the other dims wraps past 2^64; 2^21 per axis.
    static const hsize_t kHuge[] = {hsize_t{1} << 40, 2635249153387078803ull, hsize_t{1} << 21, hsize_t{1} << 33};
    const hsize_t huge = kHuge[r.Byte() % 4];
    if (dims.empty()) dims.push_back(huge);
    for (std::size_t k = 0; k < dims.size(); ++k) {
      if (k >= spec.dims.size() || spec.dims[k] < 0 || r.Byte() % 2 == 1) dims[k] = huge;
    }
    std::vector<hsize_t> chunk(dims.size(), 1);
    H5Pset_chunk(dcpl.id, static_cast<int>(chunk.size()), chunk.data());
    write_values = false;
  }
  hid_t space_id;
  if (mode == 7) {
    space_id = H5Screate(H5S_NULL);
    write_values = false;
  } else if (dims.empty()) {
    space_id = H5Screate(H5S_SCALAR);
  } else {
    space_id = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  }
  Id space{space_id, H5Sclose};
  if (space.id < 0) return;
  Id string_type{stored.type < 0 ? StringType(4) : -1, H5Tclose};
  const hid_t file_type = stored.type < 0 ? string_type.id : stored.type;
  Id dataset{H5Dcreate2(file, spec.name.c_str(), file_type, space.id, lcpl, dcpl.id, H5P_DEFAULT), H5Dclose};
  if (dataset.id < 0 || !write_values) return;

  std::size_t count = 1;
  for (hsize_t d : dims) count *= static_cast<std::size_t>(d);
  if (count == 0) return;
  if (stored.type < 0) {
    std::vector<char> text(4 * count);
    for (char& c : text) c = static_cast<char>(r.Byte());
    H5Dwrite(dataset.id, file_type, H5S_ALL, H5S_ALL, dxpl, text.data());
    return;
  }
  std::vector<double> doubles(count);
  std::vector<std::int64_t> ints(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double typical = spec.values.empty() ? 0.0 : spec.values[i % spec.values.size()];
    const Value v = i < 4096 ? PaletteValue(r, typical) : Value{typical, static_cast<std::int64_t>(typical)};
    doubles[i] = v.d;
    ints[i] = v.i;
  }
  if (stored.is_float) {
    H5Dwrite(dataset.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, dxpl, doubles.data());
  } else {
    H5Dwrite(dataset.id, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, dxpl, ints.data());
  }
}

void WriteAttribute(hid_t file, const AttributeSpec& spec, Recipe& r) {
  const std::uint8_t mode = r.Byte() % 6;
  if (mode == 1) return;
  const char* object = spec.object.empty() ? "/" : spec.object.c_str();
  if (H5Oexists_by_name(file, object, H5P_DEFAULT) <= 0) return;  // its dataset was left out
  Id target{H5Oopen(file, object, H5P_DEFAULT), H5Oclose};
  if (target.id < 0) return;

  Kind kind = spec.kind;
  if (mode == 2) kind = kind == Kind::kString ? Kind::kDouble : Kind::kString;
  hsize_t elements = mode == 5 ? 2 : 1;
  Id space{H5Screate_simple(1, &elements, nullptr), H5Sclose};
  if (kind == Kind::kString) {
    std::string text = mode == 0 || mode == 5 ? spec.text : mode == 3 ? r.Text() : "x";
    if (mode == 4) {
      Id type{H5Tcopy(H5T_C_S1), H5Tclose};
      H5Tset_size(type.id, H5T_VARIABLE);
      Id attr{H5Acreate2(target.id, spec.name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
      const char* values[1] = {text.c_str()};
      if (attr.id >= 0) H5Awrite(attr.id, type.id, values);
      return;
    }
    const std::size_t slot = std::max<std::size_t>(text.size(), 1);
    Id type{StringType(slot), H5Tclose};
    std::string buffer(slot * elements, '\0');
    for (hsize_t e = 0; e < elements; ++e) buffer.replace(e * slot, text.size(), text);
    Id attr{H5Acreate2(target.id, spec.name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    if (attr.id >= 0) H5Awrite(attr.id, type.id, buffer.data());
    return;
  }
  Value value{spec.number, static_cast<std::int64_t>(spec.number)};
  if (mode == 3) value = PaletteValue(r, spec.number);
  hid_t file_type = kind == Kind::kInt64 ? H5T_STD_I64LE : H5T_IEEE_F64LE;
  if (mode == 4) file_type = kind == Kind::kInt64 ? H5T_STD_I32LE : H5T_IEEE_F32LE;
  if (mode == 2) file_type = H5T_IEEE_F64LE;
  Id attr{H5Acreate2(target.id, spec.name.c_str(), file_type, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  if (attr.id < 0) return;
  const bool as_int = kind == Kind::kInt64 && mode != 2;
  const double doubles[2] = {value.d, value.d};
  const std::int64_t ints[2] = {value.i, value.i};
  if (as_int) {
    H5Awrite(attr.id, H5T_NATIVE_INT64, ints);
  } else {
    H5Awrite(attr.id, H5T_NATIVE_DOUBLE, doubles);
  }
}

}  // namespace

void WriteRecipeArtifact(const ArtifactSpec& spec, const std::uint8_t* data, std::size_t size,
                         const std::filesystem::path& path) {
  static const bool quiet = [] {
    H5open();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    // Keep HDF5's freed blocks for reuse (no limits on its free lists):
    // otherwise every file open callocs its ~1 MB metadata cache afresh,
    // which under ASan is an mmap and page faults, 15 ms per run instead
    // of about 1 ms.
    H5set_free_list_limits(-1, -1, -1, -1, -1, -1);
    return true;
  }();
  (void)quiet;
  // Property lists made once. Type conversion on writing uses a 64 KB
  // buffer instead of HDF5's default 1 MB, which it callocs (clears) on
  // every H5Dwrite that converts (a dataset stored as uint8, float32, ...).
  static const struct Lists {
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
    Lists() {
      H5Pset_create_intermediate_group(lcpl, 1);
      H5Pset_buffer(dxpl, 64 * 1024, nullptr, nullptr);
    }
  } lists;
  Recipe r(data, size);
  Id file{H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
  if (file.id < 0) return;
  for (const DatasetSpec& dataset : spec.datasets) WriteDataset(file.id, lists.lcpl, lists.dxpl, dataset, r);

  std::vector<AttributeSpec> attributes = {
      {"", "schema", Kind::kString, spec.schema, 0},
      {"", "schema_version", Kind::kInt64, "", static_cast<double>(spec.version)},
      {"", "producer", Kind::kString, "ausbau-fuzz", 0},
      {"", "producer_version", Kind::kString, "0.0.0", 0},
      {"", "parameters", Kind::kString, "seed: 1\n", 0},
      {"", "inputs", Kind::kString, "{}", 0},
      {"", "provenance", Kind::kString, "0123456789abcdef0123456789abcdef", 0},
  };
  attributes.insert(attributes.end(), spec.attributes.begin(), spec.attributes.end());
  for (const AttributeSpec& attribute : attributes) WriteAttribute(file.id, attribute, r);
  H5Eclear2(H5E_DEFAULT);
}

}  // namespace ausbau::fuzz
