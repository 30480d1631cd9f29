// HDF5 artifacts through the HDF5 C API (see artifact.h, schemas/README.md).
//
// Conventions of this implementation:
//  - HDF5's automatic error printing is switched off once, on first use; every
//    failure becomes an exception. Problems with a file being read are
//    InputError ("<path>: <what>"); failures while writing are
//    std::runtime_error naming the target; misuse of the API (dims that do not
//    match the data, an empty name, writing after Commit) is std::logic_error.
//  - Files are byte-for-byte deterministic: object time tracking is off for
//    the root group, every group and every dataset; strings are fixed-length
//    (no global heap); all file types are explicit little-endian.
//  - Scalars: an empty dims vector means a scalar dataspace (rank 0, one
//    element); readers return dims {} for it.
//  - Strings (attributes) are fixed-length, null-padded, UTF-8. Readers also
//    accept variable-length strings (as written by h5py).
//  - Lossless reads only: a dataset or attribute is read as a type only when
//    every value of its stored type is representable (e.g. float32 -> double,
//    uint8 -> int64, int32 -> double), never float64 -> int64 or float64 ->
//    float32 or int64 -> double.
//  - Not thread-safe (the Debian HDF5 build is serial): use from one thread.
#include "artifact/artifact.h"

#include <hdf5.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <set>
#include <stdexcept>
#include <system_error>

#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/hash.h"

namespace ausbau {
namespace {

// ---------------------------------------------------------------------------
// Library setup and small helpers

void QuietHdf5() {
  static const bool done = [] {
    H5open();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

// The innermost message on HDF5's error stack (the most specific one), or "".
std::string Hdf5ErrorDetail() {
  std::string detail;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* err, void* data) -> herr_t {
        if (n == 0 && err->desc != nullptr) *static_cast<std::string*>(data) = err->desc;
        return 0;
      },
      &detail);
  H5Eclear2(H5E_DEFAULT);
  return detail;
}

// An owned HDF5 identifier, closed with the matching H5?close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  ~Handle() { Reset(); }
  Handle(Handle&& other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      Reset();
      id_ = other.id_;
      closer_ = other.closer_;
      other.id_ = -1;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  bool valid() const { return id_ >= 0; }
  hid_t get() const { return id_; }
  // Closes now and reports whether closing succeeded.
  bool Close() {
    if (id_ < 0) return true;
    const herr_t status = closer_(id_);
    id_ = -1;
    return status >= 0;
  }
  void Reset() { Close(); }

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

Handle PropertyList(hid_t cls) { return Handle(H5Pcreate(cls), H5Pclose); }

// Splits "a/b/c" (a leading '/' is allowed) into {"a", "b", "c"}; throws
// std::logic_error on an empty component.
std::vector<std::string> SplitPath(const std::string& name) {
  std::vector<std::string> parts;
  std::size_t start = (!name.empty() && name[0] == '/') ? 1 : 0;
  while (start <= name.size()) {
    const std::size_t slash = name.find('/', start);
    const std::size_t end = slash == std::string::npos ? name.size() : slash;
    parts.push_back(name.substr(start, end - start));
    if (parts.back().empty() || parts.back() == "." || parts.back() == "..") {
      throw std::logic_error("invalid artifact object name '" + name + "'");
    }
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return parts;
}

bool IsRoot(const std::string& object) { return object.empty() || object == "/"; }

std::string Join(const std::vector<std::string>& parts, std::size_t count) {
  std::string out;
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) out += '/';
    out += parts[i];
  }
  return out;
}

std::size_t ElementCount(const std::vector<std::size_t>& dims) {
  std::size_t n = 1;
  for (std::size_t d : dims) n *= d;
  return n;
}

// The product of `dims`, or nothing when it does not fit in 64 bits (a
// corrupt or hostile file can declare dims whose product wraps around).
std::optional<std::uint64_t> CheckedElementCount(const std::vector<std::uint64_t>& dims) {
  for (std::uint64_t d : dims) {
    if (d == 0) return 0;
  }
  std::uint64_t n = 1;
  for (std::uint64_t d : dims) {
    if (n > std::numeric_limits<std::uint64_t>::max() / d) return std::nullopt;
    n *= d;
  }
  return n;
}

// The most bytes of data a file of `file_bytes` can hold: our writer
// compresses with shuffle + deflate, and deflate expands at most 1032:1;
// the slack covers small datasets h5py leaves unallocated (fill values).
// A dataset declaring more is refused before anything is allocated.
constexpr std::uint64_t kMaxExpansion = 1100;
constexpr std::uint64_t kDataSlackBytes = std::uint64_t{1} << 20;
std::uint64_t MaxDataBytes(std::uint64_t file_bytes) {
  const std::uint64_t cap = std::numeric_limits<std::uint64_t>::max() / 2;
  return file_bytes > cap / kMaxExpansion ? cap : file_bytes * kMaxExpansion + kDataSlackBytes;
}

std::string DimsText(const std::vector<std::size_t>& dims) {
  std::string out = "[";
  for (std::size_t i = 0; i < dims.size(); ++i) out += (i ? "," : "") + std::to_string(dims[i]);
  return out + "]";
}

// "float64", "int32", "uint8", "string", ...
std::string TypeName(hid_t type) {
  const std::size_t bits = H5Tget_size(type) * 8;
  switch (H5Tget_class(type)) {
    case H5T_INTEGER: return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + std::to_string(bits);
    case H5T_FLOAT: return "float" + std::to_string(bits);
    case H5T_STRING: return "string";
    case H5T_COMPOUND: return "compound";
    case H5T_ENUM: return "enum";
    case H5T_ARRAY: return "array";
    case H5T_VLEN: return "vlen";
    case H5T_BITFIELD: return "bitfield";
    case H5T_OPAQUE: return "opaque";
    case H5T_REFERENCE: return "reference";
    case H5T_TIME: return "time";
    default: return "unknown";
  }
}

enum class Target { kDouble, kFloat, kInt64, kUint8 };

const char* TargetName(Target target) {
  switch (target) {
    case Target::kDouble: return "float64";
    case Target::kFloat: return "float32";
    case Target::kInt64: return "int64";
    case Target::kUint8: return "uint8";
  }
  return "?";
}

hid_t MemoryType(Target target) {
  switch (target) {
    case Target::kDouble: return H5T_NATIVE_DOUBLE;
    case Target::kFloat: return H5T_NATIVE_FLOAT;
    case Target::kInt64: return H5T_NATIVE_INT64;
    case Target::kUint8: return H5T_NATIVE_UINT8;
  }
  return -1;
}

// Whether every value of the stored type converts to `target` exactly.
bool ConvertsLosslessly(hid_t stored, Target target) {
  const H5T_class_t cls = H5Tget_class(stored);
  const std::size_t size = H5Tget_size(stored);
  const bool is_signed = H5Tget_sign(stored) != H5T_SGN_NONE;
  switch (target) {
    case Target::kDouble:  // 53-bit mantissa: integers up to 32 bits
      return (cls == H5T_FLOAT && size <= 8) || (cls == H5T_INTEGER && size <= 4);
    case Target::kFloat:  // 24-bit mantissa: integers up to 16 bits
      return (cls == H5T_FLOAT && size <= 4) || (cls == H5T_INTEGER && size <= 2);
    case Target::kInt64: return cls == H5T_INTEGER && (is_signed ? size <= 8 : size <= 4);
    case Target::kUint8: return cls == H5T_INTEGER && !is_signed && size == 1;
  }
  return false;
}

// ---------------------------------------------------------------------------
// Writing helpers

void CheckTarget(herr_t status, const std::filesystem::path& target, const std::string& what) {
  if (status < 0) {
    const std::string detail = Hdf5ErrorDetail();
    throw std::runtime_error(target.string() + ": " + what + (detail.empty() ? std::string() : " (" + detail + ")"));
  }
}

hid_t CheckTargetId(hid_t id, const std::filesystem::path& target, const std::string& what) {
  CheckTarget(id < 0 ? -1 : 0, target, what);
  return id;
}

Handle StringType(std::size_t length, hid_t base) {
  Handle type(H5Tcopy(base), H5Tclose);
  if (!type.valid() || H5Tset_size(type.get(), std::max<std::size_t>(length, 1)) < 0 ||
      H5Tset_strpad(type.get(), H5T_STR_NULLPAD) < 0 || H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0) {
    return Handle();
  }
  return type;
}

std::string InputsYaml(const std::vector<std::pair<std::string, std::string>>& inputs) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  for (const auto& [role, hash] : inputs) out << YAML::Key << role << YAML::Value << hash;
  out << YAML::EndMap;
  return out.c_str();
}

const std::set<std::string>& ReservedRootAttributes() {
  static const std::set<std::string> names = {"schema",     "schema_version", "producer",  "producer_version",
                                              "parameters", "inputs",         "provenance"};
  return names;
}

}  // namespace

// ---------------------------------------------------------------------------
// Provenance

std::string Provenance::Hash() const {
  Hasher hasher;
  hasher.Add(std::string_view(producer));
  hasher.Add(std::string_view(producer_version));
  hasher.Add(std::string_view(parameters_yaml));
  for (const auto& [role, hash] : inputs) {
    hasher.Add(std::string_view(role));
    hasher.Add(std::string_view(hash));
  }
  return hasher.HexDigest();
}

// ---------------------------------------------------------------------------
// ArtifactWriter

struct ArtifactWriter::Impl {
  std::filesystem::path target;
  std::filesystem::path temp;
  Handle file;
  bool committed = false;

  void EnsureOpen() const {
    if (committed || !file.valid()) {
      throw std::logic_error(target.string() + ": artifact already committed or closed");
    }
  }

  // Creates the groups above `parts.back()`, without time stamps.
  void CreateParents(const std::vector<std::string>& parts) {
    for (std::size_t i = 1; i < parts.size(); ++i) {
      const std::string group = Join(parts, i);
      const htri_t exists = H5Lexists(file.get(), group.c_str(), H5P_DEFAULT);
      CheckTarget(exists < 0 ? -1 : 0, target, "cannot look up group '" + group + "'");
      if (exists > 0) continue;
      Handle gcpl = PropertyList(H5P_GROUP_CREATE);
      CheckTarget(gcpl.valid() ? H5Pset_obj_track_times(gcpl.get(), 0) : -1, target,
                  "cannot set up group '" + group + "'");
      Handle g(CheckTargetId(H5Gcreate2(file.get(), group.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), target,
                             "cannot create group '" + group + "'"),
               H5Gclose);
    }
  }

  void WriteDataset(const std::string& name, const void* data, std::size_t count, std::size_t element_size,
                    const std::vector<std::size_t>& dims, hid_t memory_type, hid_t file_type) {
    EnsureOpen();
    const std::vector<std::string> parts = SplitPath(name);
    if (ElementCount(dims) != count) {
      throw std::logic_error(target.string() + ": dataset '" + name + "' has " + std::to_string(count) +
                             " values but dims " + DimsText(dims));
    }
    CreateParents(parts);
    const std::string path = Join(parts, parts.size());

    std::vector<hsize_t> hdims(dims.begin(), dims.end());
    Handle space(CheckTargetId(dims.empty() ? H5Screate(H5S_SCALAR)
                                            : H5Screate_simple(static_cast<int>(hdims.size()), hdims.data(), nullptr),
                               target, "cannot create dataspace for '" + name + "'"),
                 H5Sclose);

    Handle dcpl = PropertyList(H5P_DATASET_CREATE);
    CheckTargetId(dcpl.get(), target, "cannot set up dataset '" + name + "'");
    CheckTarget(H5Pset_obj_track_times(dcpl.get(), 0), target, "cannot set up dataset '" + name + "'");
    CheckTarget(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), target, "cannot set up dataset '" + name + "'");
    const std::size_t bytes = count * element_size;
    if (bytes > 64 * 1024 && !dims.empty()) {
      // Chunks of at most 512 KiB, split along the leading dimensions.
      std::vector<hsize_t> chunk = hdims;
      auto chunk_bytes = [&] {
        std::size_t b = element_size;
        for (hsize_t c : chunk) b *= c;
        return b;
      };
      while (chunk_bytes() > 512 * 1024) {
        auto it = std::find_if(chunk.begin(), chunk.end(), [](hsize_t c) { return c > 1; });
        if (it == chunk.end()) break;
        *it = (*it + 1) / 2;
      }
      CheckTarget(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), target,
                  "cannot set chunking for '" + name + "'");
      CheckTarget(H5Pset_shuffle(dcpl.get()), target, "cannot set shuffle filter for '" + name + "'");
      CheckTarget(H5Pset_deflate(dcpl.get(), 4), target, "cannot set deflate filter for '" + name + "'");
    }

    Handle dataset(CheckTargetId(H5Dcreate2(file.get(), path.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(),
                                            H5P_DEFAULT),
                                 target, "cannot create dataset '" + name + "'"),
                   H5Dclose);
    if (count > 0) {
      CheckTarget(H5Dwrite(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), target,
                  "cannot write dataset '" + name + "'");
    }
    CheckTarget(dataset.Close() ? 0 : -1, target, "cannot close dataset '" + name + "'");
  }

  // Calls write(object_id) with the root group or the named object opened.
  template <typename Write>
  void WithObject(const std::string& object, const std::string& attribute, Write write) {
    EnsureOpen();
    Handle obj;
    if (IsRoot(object)) {
      obj = Handle(CheckTargetId(H5Gopen2(file.get(), "/", H5P_DEFAULT), target, "cannot open root group"), H5Gclose);
    } else {
      const std::string path = Join(SplitPath(object), SplitPath(object).size());
      obj = Handle(CheckTargetId(H5Oopen(file.get(), path.c_str(), H5P_DEFAULT), target,
                                 "cannot open object '" + object + "' for attribute '" + attribute + "'"),
                   H5Oclose);
    }
    const htri_t exists = H5Aexists(obj.get(), attribute.c_str());
    CheckTarget(exists < 0 ? -1 : 0, target, "cannot look up attribute '" + attribute + "'");
    if (exists > 0) {
      CheckTarget(H5Adelete(obj.get(), attribute.c_str()), target, "cannot replace attribute '" + attribute + "'");
    }
    write(obj.get());
  }

  void WriteAttribute(hid_t obj, const std::string& name, hid_t file_type, hid_t memory_type, const void* value) {
    Handle space(CheckTargetId(H5Screate(H5S_SCALAR), target, "cannot create dataspace"), H5Sclose);
    Handle attr(CheckTargetId(H5Acreate2(obj, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), target,
                              "cannot create attribute '" + name + "'"),
                H5Aclose);
    CheckTarget(H5Awrite(attr.get(), memory_type, value), target, "cannot write attribute '" + name + "'");
  }

  void WriteStringAttribute(hid_t obj, const std::string& name, const std::string& value) {
    Handle type = StringType(value.size(), H5T_C_S1);
    CheckTargetId(type.get(), target, "cannot create string type for attribute '" + name + "'");
    std::vector<char> buffer(std::max<std::size_t>(value.size(), 1), '\0');
    std::memcpy(buffer.data(), value.data(), value.size());
    WriteAttribute(obj, name, type.get(), type.get(), buffer.data());
  }
};

ArtifactWriter::ArtifactWriter(std::filesystem::path path, std::string schema, int schema_version,
                               const Provenance& provenance)
    : impl_(new Impl) {
  try {
    QuietHdf5();
    impl_->target = std::move(path);
    {
      std::set<std::string> roles;
      for (const auto& input : provenance.inputs) {
        if (!roles.insert(input.first).second) {
          throw std::logic_error(impl_->target.string() + ": duplicate input role '" + input.first + "'");
        }
      }
    }
    const std::filesystem::path parent = impl_->target.parent_path();
    if (!parent.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(parent, ec);
      if (ec) {
        throw std::runtime_error(impl_->target.string() + ": cannot create directory '" + parent.string() + "' (" +
                                 ec.message() + ")");
      }
    }
    // Never replace a link, FIFO or device; clear what killed writers left.
    CheckOutputTarget(impl_->target);
    RemoveStaleTemporaries(impl_->target);
    const std::filesystem::path temporary = TemporaryPathFor(impl_->target);

    Handle fcpl = PropertyList(H5P_FILE_CREATE);
    CheckTargetId(fcpl.get(), impl_->target, "cannot set up file creation");
    CheckTarget(H5Pset_obj_track_times(fcpl.get(), 0), impl_->target, "cannot set up file creation");
    Handle fapl = PropertyList(H5P_FILE_ACCESS);
    CheckTargetId(fapl.get(), impl_->target, "cannot set up file access");
    CheckTarget(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), impl_->target, "cannot set up file access");
    // H5F_ACC_EXCL (O_CREAT | O_EXCL): the temporary is a new file of ours;
    // a name that exists already (a link planted under it, pointing outside
    // the output folder) is refused, not written through, and left alone.
    impl_->file = Handle(CheckTargetId(H5Fcreate(temporary.c_str(), H5F_ACC_EXCL, fcpl.get(), fapl.get()),
                                       impl_->target, "cannot create temporary file '" + temporary.string() + "'"),
                         H5Fclose);
    impl_->temp = temporary;

    const std::int64_t version = schema_version;
    impl_->WithObject("", "schema", [&](hid_t root) { impl_->WriteStringAttribute(root, "schema", schema); });
    impl_->WithObject("", "schema_version", [&](hid_t root) {
      impl_->WriteAttribute(root, "schema_version", H5T_STD_I64LE, H5T_NATIVE_INT64, &version);
    });
    const std::pair<const char*, std::string> strings[] = {
        {"producer", provenance.producer},          {"producer_version", provenance.producer_version},
        {"parameters", provenance.parameters_yaml}, {"inputs", InputsYaml(provenance.inputs)},
        {"provenance", provenance.Hash()},
    };
    for (const auto& entry : strings) {
      impl_->WithObject("", entry.first,
                        [&](hid_t root) { impl_->WriteStringAttribute(root, entry.first, entry.second); });
    }
  } catch (...) {
    impl_->file.Reset();
    if (!impl_->temp.empty()) {
      std::error_code ec;
      std::filesystem::remove(impl_->temp, ec);
    }
    delete impl_;
    throw;
  }
}

ArtifactWriter::~ArtifactWriter() {
  if (!impl_->committed) {
    impl_->file.Reset();
    std::error_code ec;
    std::filesystem::remove(impl_->temp, ec);
  }
  delete impl_;
}

void ArtifactWriter::WriteDoubles(const std::string& name, const std::vector<double>& data,
                                  const std::vector<std::size_t>& dims) {
  impl_->WriteDataset(name, data.data(), data.size(), sizeof(double), dims, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE);
}

void ArtifactWriter::WriteFloats(const std::string& name, const std::vector<float>& data,
                                 const std::vector<std::size_t>& dims) {
  impl_->WriteDataset(name, data.data(), data.size(), sizeof(float), dims, H5T_NATIVE_FLOAT, H5T_IEEE_F32LE);
}

void ArtifactWriter::WriteInts(const std::string& name, const std::vector<std::int64_t>& data,
                               const std::vector<std::size_t>& dims) {
  impl_->WriteDataset(name, data.data(), data.size(), sizeof(std::int64_t), dims, H5T_NATIVE_INT64, H5T_STD_I64LE);
}

void ArtifactWriter::WriteBytes(const std::string& name, const std::vector<std::uint8_t>& data,
                                const std::vector<std::size_t>& dims) {
  impl_->WriteDataset(name, data.data(), data.size(), 1, dims, H5T_NATIVE_UINT8, H5T_STD_U8LE);
}

namespace {
void CheckNotReserved(const std::filesystem::path& target, const std::string& object, const std::string& name) {
  if (IsRoot(object) && ReservedRootAttributes().count(name) > 0) {
    throw std::logic_error(target.string() + ": root attribute '" + name + "' is reserved");
  }
}
}  // namespace

void ArtifactWriter::SetAttribute(const std::string& object, const std::string& name, const std::string& value) {
  CheckNotReserved(impl_->target, object, name);
  impl_->WithObject(object, name, [&](hid_t obj) { impl_->WriteStringAttribute(obj, name, value); });
}

void ArtifactWriter::SetAttribute(const std::string& object, const std::string& name, double value) {
  CheckNotReserved(impl_->target, object, name);
  impl_->WithObject(object, name,
                    [&](hid_t obj) { impl_->WriteAttribute(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value); });
}

void ArtifactWriter::SetAttribute(const std::string& object, const std::string& name, std::int64_t value) {
  CheckNotReserved(impl_->target, object, name);
  impl_->WithObject(object, name,
                    [&](hid_t obj) { impl_->WriteAttribute(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value); });
}

void ArtifactWriter::Commit() {
  impl_->EnsureOpen();
  CheckTarget(H5Fflush(impl_->file.get(), H5F_SCOPE_GLOBAL), impl_->target, "cannot flush temporary file");
  CheckTarget(impl_->file.Close() ? 0 : -1, impl_->target, "cannot close temporary file");
  ThrowIfCancelled();  // a cancelled run commits nothing (core/cancel.h); the destructor removes the temporary
  std::error_code ec;
  std::filesystem::rename(impl_->temp, impl_->target, ec);
  if (ec) {
    throw std::runtime_error(impl_->target.string() + ": cannot rename temporary file onto target (" + ec.message() +
                             ")");
  }
  impl_->committed = true;
}

// ---------------------------------------------------------------------------
// ArtifactReader

// The first link or dataset of an open file whose data lives outside it,
// described ("'waypoints' is an external link to other.h5:/w"), or "" when
// every object is the file's own. Our writers only make hard links and
// contiguous or chunked datasets; anything else was put there by hand. An
// external link (or a soft link, which can lead into one, or a link type
// of a plugin), an external raw-data file or a virtual dataset would be
// followed on reading, while the provenance and every content hash see
// only this file: an edit of the other file would pass as unchanged.
std::string ForeignStorage(hid_t file) {
  struct Found {
    std::string what;
  } found;
  const H5L_iterate_t visit = [](hid_t group, const char* name, const auto* info, void* data) -> herr_t {
    std::string& what = static_cast<Found*>(data)->what;
    const std::string quoted = "'" + std::string(name) + "'";
    if (info->type == H5L_TYPE_EXTERNAL) {
      what = quoted + " is an external link";
      std::vector<char> value(info->u.val_size + 1, '\0');
      const char* target_file = nullptr;
      const char* target_object = nullptr;
      if (H5Lget_val(group, name, value.data(), value.size(), H5P_DEFAULT) >= 0 &&
          H5Lunpack_elink_val(value.data(), info->u.val_size, nullptr, &target_file, &target_object) >= 0 &&
          target_file != nullptr && target_object != nullptr) {
        what += " to " + std::string(target_file) + ":" + target_object;
      }
      return 1;
    }
    if (info->type == H5L_TYPE_SOFT) {
      what = quoted + " is a soft link";
      return 1;
    }
    if (info->type != H5L_TYPE_HARD) {
      what = quoted + " is a link of a user-defined type";
      return 1;
    }
    const hid_t object = H5Oopen(group, name, H5P_DEFAULT);
    if (object < 0) return 0;  // unreadable objects fail where they are read
    if (H5Iget_type(object) == H5I_DATASET) {
      const hid_t plist = H5Dget_create_plist(object);
      if (plist >= 0) {
        if (H5Pget_layout(plist) == H5D_VIRTUAL) {
          what = quoted + " is a virtual dataset (its data lives in other files)";
        } else if (H5Pget_external_count(plist) > 0) {
          what = quoted + " keeps its data in an external file";
        }
        H5Pclose(plist);
      }
    }
    H5Oclose(object);
    return what.empty() ? 0 : 1;
  };
  H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, visit, &found);
  H5Eclear2(H5E_DEFAULT);
  return found.what;
}

struct ArtifactReader::Impl {
  std::filesystem::path path;
  std::uint64_t file_bytes = 0;  // bounds what a dataset may declare (MaxDataBytes)
  Handle file;
  std::string provenance;
  std::string parameters;
  std::string producer;

  [[noreturn]] void Fail(const std::string& what) const {
    H5Eclear2(H5E_DEFAULT);
    throw InputErrorAt(path.string(), what);
  }

  static std::string Describe(const std::string& object, const std::string& attribute) {
    return IsRoot(object) ? "root attribute '" + attribute + "'" : "attribute '" + attribute + "' on '" + object + "'";
  }

  bool Has(const std::string& name) const {
    if (IsRoot(name)) return true;
    std::vector<std::string> parts;
    try {
      parts = SplitPath(name);
    } catch (const std::logic_error&) {
      return false;
    }
    for (std::size_t i = 1; i <= parts.size(); ++i) {
      const std::string prefix = Join(parts, i);
      if (H5Lexists(file.get(), prefix.c_str(), H5P_DEFAULT) <= 0) {
        H5Eclear2(H5E_DEFAULT);
        return false;
      }
    }
    // The link may dangle (a soft link to nothing).
    const std::string full = Join(parts, parts.size());
    const htri_t resolves = H5Oexists_by_name(file.get(), full.c_str(), H5P_DEFAULT);
    H5Eclear2(H5E_DEFAULT);
    return resolves > 0;
  }

  // Opens the attribute `name` of `object` and returns it with its type.
  std::pair<Handle, Handle> OpenAttribute(const std::string& object, const std::string& name) const {
    Handle obj;
    if (IsRoot(object)) {
      obj = Handle(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose);
      if (!obj.valid()) Fail("cannot open root group (corrupt file?)");
    } else {
      if (!Has(object)) Fail("missing object '" + object + "'");
      const std::vector<std::string> parts = SplitPath(object);
      obj = Handle(H5Oopen(file.get(), Join(parts, parts.size()).c_str(), H5P_DEFAULT), H5Oclose);
      if (!obj.valid()) Fail("cannot open object '" + object + "' (corrupt file?)");
    }
    const htri_t exists = H5Aexists(obj.get(), name.c_str());
    if (exists < 0) Fail("cannot read " + Describe(object, name) + " (corrupt file?)");
    if (exists == 0) Fail("missing " + Describe(object, name));
    Handle attr(H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
    if (!attr.valid()) Fail("cannot read " + Describe(object, name) + " (corrupt file?)");
    Handle space(H5Aget_space(attr.get()), H5Sclose);
    const hssize_t points = space.valid() ? H5Sget_simple_extent_npoints(space.get()) : -1;
    if (points != 1) {
      Fail(Describe(object, name) + " has " + std::to_string(static_cast<long long>(points)) +
           " elements (expected 1)");
    }
    Handle type(H5Aget_type(attr.get()), H5Tclose);
    if (!type.valid()) Fail("cannot read " + Describe(object, name) + " (corrupt file?)");
    return {std::move(attr), std::move(type)};
  }

  std::string ReadString(const std::string& object, const std::string& name) const {
    auto [attr, type] = OpenAttribute(object, name);
    if (H5Tget_class(type.get()) != H5T_STRING) {
      Fail(Describe(object, name) + " has type " + TypeName(type.get()) + " (expected string)");
    }
    const htri_t variable = H5Tis_variable_str(type.get());
    if (variable < 0) Fail("cannot read " + Describe(object, name) + " (corrupt file?)");
    if (variable > 0) {
      Handle memory_type(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(memory_type.get(), H5T_VARIABLE);
      H5Tset_cset(memory_type.get(), H5Tget_cset(type.get()));
      char* text = nullptr;
      if (H5Aread(attr.get(), memory_type.get(), &text) < 0) {
        Fail("cannot read " + Describe(object, name) + " (corrupt file?)");
      }
      std::string value = text != nullptr ? text : "";
      H5free_memory(text);
      return value;
    }
    const std::size_t size = H5Tget_size(type.get());
    if (size == 0 || size > MaxDataBytes(file_bytes)) {
      Fail(Describe(object, name) + " declares a string of " + std::to_string(size) + " bytes in a file of " +
           std::to_string(file_bytes) + " bytes (truncated or corrupt file?)");
    }
    std::vector<char> buffer(size + 1, '\0');
    if (H5Aread(attr.get(), type.get(), buffer.data()) < 0) {
      Fail("cannot read " + Describe(object, name) + " (corrupt file?)");
    }
    std::string value(buffer.data(), size);
    if (H5Tget_strpad(type.get()) == H5T_STR_SPACEPAD) {
      value.erase(value.find_last_not_of(' ') + 1);
    } else {
      const std::size_t nul = value.find('\0');
      if (nul != std::string::npos) value.resize(nul);
    }
    return value;
  }

  template <typename T>
  T ReadNumber(const std::string& object, const std::string& name, Target target) const {
    auto [attr, type] = OpenAttribute(object, name);
    if (!ConvertsLosslessly(type.get(), target)) {
      Fail(Describe(object, name) + " has type " + TypeName(type.get()) + " (expected a type convertible to " +
           TargetName(target) + " without loss)");
    }
    T value{};
    if (H5Aread(attr.get(), MemoryType(target), &value) < 0) {
      Fail("cannot read " + Describe(object, name) + " (corrupt file?)");
    }
    return value;
  }

  template <typename T>
  Array<T> ReadArray(const std::string& name, int expected_rank, Target target) const {
    if (IsRoot(name) || !Has(name)) Fail("missing dataset '" + name + "'");
    const std::vector<std::string> parts = SplitPath(name);
    const std::string full = Join(parts, parts.size());
    H5O_info_t info;
    if (H5Oget_info_by_name(file.get(), full.c_str(), &info, H5P_DEFAULT) < 0) {
      Fail("cannot read dataset '" + name + "' (corrupt file?)");
    }
    if (info.type != H5O_TYPE_DATASET) Fail("'" + name + "' is not a dataset");
    Handle dataset(H5Dopen2(file.get(), full.c_str(), H5P_DEFAULT), H5Dclose);
    if (!dataset.valid()) Fail("cannot open dataset '" + name + "' (corrupt file?)");
    Handle space(H5Dget_space(dataset.get()), H5Sclose);
    Handle type(H5Dget_type(dataset.get()), H5Tclose);
    if (!space.valid() || !type.valid()) Fail("cannot read dataset '" + name + "' (corrupt file?)");

    Array<T> out;
    const H5S_class_t space_class = H5Sget_simple_extent_type(space.get());
    if (space_class == H5S_NULL) Fail("dataset '" + name + "' has no dataspace (H5S_NULL)");
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank < 0) Fail("cannot read dataset '" + name + "' (corrupt file?)");
    if (expected_rank >= 0 && rank != expected_rank) {
      Fail("dataset '" + name + "' has rank " + std::to_string(rank) + " (expected " + std::to_string(expected_rank) +
           ")");
    }
    if (!ConvertsLosslessly(type.get(), target)) {
      Fail("dataset '" + name + "' has type " + TypeName(type.get()) + " (expected a type convertible to " +
           TargetName(target) + " without loss)");
    }
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0) {
      Fail("cannot read dataset '" + name + "' (corrupt file?)");
    }
    // Bound the allocation by what the file can hold, before allocating:
    // a 46 KB file can declare a 64 GB dataset (or dims whose product wraps
    // past 2^64, which would under-allocate and overflow the buffer).
    const std::vector<std::uint64_t> dims64(dims.begin(), dims.end());
    const std::optional<std::uint64_t> count = CheckedElementCount(dims64);
    const std::uint64_t element_bytes = std::max<std::uint64_t>(H5Tget_size(type.get()), sizeof(T));
    if (!count || *count > MaxDataBytes(file_bytes) / element_bytes) {
      Fail("dataset '" + name + "' declares " + DimsText(std::vector<std::size_t>(dims.begin(), dims.end())) +
           " elements, more than a file of " + std::to_string(file_bytes) +
           " bytes can hold (truncated or corrupt file?)");
    }
    out.dims.assign(dims.begin(), dims.end());
    out.data.resize(static_cast<std::size_t>(*count));
    if (!out.data.empty() &&
        H5Dread(dataset.get(), MemoryType(target), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data.data()) < 0) {
      Fail("cannot read dataset '" + name + "' (truncated or corrupt file?)");
    }
    return out;
  }
};

ArtifactReader::ArtifactReader(std::filesystem::path path, const std::string& schema, int schema_version)
    : impl_(new Impl) {
  try {
    QuietHdf5();
    impl_->path = std::move(path);
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(impl_->path, ec);
    if (!std::filesystem::exists(status)) impl_->Fail("file not found");
    if (std::filesystem::is_directory(status)) impl_->Fail("is a directory (expected an HDF5 file)");
    // A FIFO or a device (/dev/zero) is no artifact: refuse it before HDF5
    // blocks on it or reads it without end.
    if (!std::filesystem::is_regular_file(status)) impl_->Fail("not a regular file (expected an HDF5 file)");
    impl_->file_bytes = std::filesystem::file_size(impl_->path, ec);
    if (ec) impl_->Fail("cannot read file size (" + ec.message() + ")");

    Handle fapl = PropertyList(H5P_FILE_ACCESS);
    if (!fapl.valid() || H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG) < 0) {
      impl_->Fail("cannot set up file access");
    }
#if H5_VERS_MAJOR > 1 ||                                                                           \
    (H5_VERS_MAJOR == 1 && (H5_VERS_MINOR > 12 || (H5_VERS_MINOR == 12 && H5_VERS_RELEASE >= 1) || \
                            (H5_VERS_MINOR == 10 && H5_VERS_RELEASE >= 7)))
    // Read-only: where the file system has no locks (NFS), read anyway.
    H5Pset_file_locking(fapl.get(), true, true);
#endif
    impl_->file = Handle(H5Fopen(impl_->path.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose);
    if (!impl_->file.valid()) impl_->Fail("not a readable HDF5 file (truncated or corrupt?)");
    const std::string foreign = ForeignStorage(impl_->file.get());
    if (!foreign.empty()) {
      impl_->Fail(foreign + ": an artifact must hold all its data itself (links and data in other files are refused)");
    }

    const std::string actual_schema = impl_->ReadString("", "schema");
    if (actual_schema != schema) {
      impl_->Fail("wrong schema (expected " + schema + ", got " + actual_schema + ")");
    }
    const std::int64_t actual_version = impl_->ReadNumber<std::int64_t>("", "schema_version", Target::kInt64);
    if (actual_version != schema_version) {
      impl_->Fail("unsupported schema version (expected " + std::to_string(schema_version) + ", got " +
                  std::to_string(actual_version) + ")");
    }
    impl_->producer = impl_->ReadString("", "producer");
    impl_->parameters = impl_->ReadString("", "parameters");
    impl_->provenance = impl_->ReadString("", "provenance");
  } catch (...) {
    delete impl_;
    throw;
  }
}

ArtifactReader::~ArtifactReader() { delete impl_; }

const std::filesystem::path& ArtifactReader::path() const { return impl_->path; }
std::string ArtifactReader::provenance_hash() const { return impl_->provenance; }
std::string ArtifactReader::parameters_yaml() const { return impl_->parameters; }
std::string ArtifactReader::producer() const { return impl_->producer; }

bool ArtifactReader::Has(const std::string& name) const { return impl_->Has(name); }

Array<double> ArtifactReader::ReadDoubles(const std::string& name, int expected_rank) const {
  return impl_->ReadArray<double>(name, expected_rank, Target::kDouble);
}

Array<float> ArtifactReader::ReadFloats(const std::string& name, int expected_rank) const {
  return impl_->ReadArray<float>(name, expected_rank, Target::kFloat);
}

Array<std::int64_t> ArtifactReader::ReadInts(const std::string& name, int expected_rank) const {
  return impl_->ReadArray<std::int64_t>(name, expected_rank, Target::kInt64);
}

Array<std::uint8_t> ArtifactReader::ReadBytes(const std::string& name, int expected_rank) const {
  return impl_->ReadArray<std::uint8_t>(name, expected_rank, Target::kUint8);
}

std::string ArtifactReader::ReadStringAttribute(const std::string& object, const std::string& name) const {
  return impl_->ReadString(object, name);
}

double ArtifactReader::ReadDoubleAttribute(const std::string& object, const std::string& name) const {
  return impl_->ReadNumber<double>(object, name, Target::kDouble);
}

std::int64_t ArtifactReader::ReadIntAttribute(const std::string& object, const std::string& name) const {
  return impl_->ReadNumber<std::int64_t>(object, name, Target::kInt64);
}

// ---------------------------------------------------------------------------

std::optional<std::string> ExistingProvenanceHash(const std::filesystem::path& path, const std::string& schema,
                                                  int schema_version) {
  try {
    ArtifactReader reader(path, schema, schema_version);
    return reader.provenance_hash();
  } catch (...) {
    return std::nullopt;
  }
}

}  // namespace ausbau
