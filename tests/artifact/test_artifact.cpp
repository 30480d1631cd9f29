// Tests of the HDF5 artifact layer (common/artifact): round trips, provenance,
// determinism, atomic writes and every rejection a reader must make.
#include "artifact/artifact.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSchema = "ausbau-test";

Provenance SampleProvenance() {
  Provenance p;
  p.producer = "ausbau-test";
  p.producer_version = "0.1.0";
  p.parameters_yaml = "seed: 1\nrange: 0.5\n";
  p.inputs = {{"scene", "00112233445566778899aabbccddeeff"}, {"path", "ffeeddccbbaa99887766554433221100"}};
  return p;
}

std::vector<double> LargeDoubles() {
  std::vector<double> v(30000 * 3);  // 720 KB: chunked and compressed
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.001 * static_cast<double>(i % 977) - 0.25;
  return v;
}

// Writes a sample artifact with every kind of dataset and attribute.
void WriteSample(const fs::path& path, const Provenance& provenance = SampleProvenance(),
                 const std::string& schema = kSchema, int version = 1) {
  ArtifactWriter w(path, schema, version, provenance);
  w.WriteDoubles("waypoints", {1.0, 2.0, 3.0, 4.5, -5.0, 6.25}, {2, 3});
  w.SetAttribute("waypoints", "units", std::string("m"));
  w.WriteFloats("floats", {0.5f, 1.5f, -2.5f, 3.0f}, {4});
  w.WriteInts("stats/iterations", {42}, {});
  w.WriteDoubles("stats/time_s", {0.125}, {});
  w.WriteBytes("deep/er/bytes", {1, 2, 3, 4, 5, 6, 7, 255}, {2, 2, 2});
  w.WriteDoubles("large", LargeDoubles(), {30000, 3});
  w.WriteDoubles("empty", {}, {0, 7});
  w.SetAttribute("", "planner", std::string("rrt-connect"));
  w.SetAttribute("", "scale", 2.5);
  w.SetAttribute("stats", "count", std::int64_t{-7});
  w.Commit();
}

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Asserts that `f` throws InputError whose message contains `expected`.
void ExpectInputError(const std::function<void()>& f, const std::string& expected) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected InputError containing: " << expected;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << expected;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

class ArtifactTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("ausbau-test-artifact-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::vector<std::string> DirEntries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

// ---------------------------------------------------------------------------

TEST_F(ArtifactTest, RoundTrip) {
  const fs::path path = dir_ / "a.h5";
  WriteSample(path);
  ArtifactReader r(path, kSchema, 1);
  EXPECT_EQ(r.path(), path);
  EXPECT_EQ(r.producer(), "ausbau-test");
  EXPECT_EQ(r.parameters_yaml(), "seed: 1\nrange: 0.5\n");
  EXPECT_EQ(r.provenance_hash(), SampleProvenance().Hash());
  EXPECT_EQ(r.ReadStringAttribute("", "schema"), kSchema);
  EXPECT_EQ(r.ReadIntAttribute("", "schema_version"), 1);
  EXPECT_EQ(r.ReadStringAttribute("", "producer_version"), "0.1.0");
  EXPECT_EQ(r.ReadStringAttribute("", "inputs"),
            "scene: 00112233445566778899aabbccddeeff\npath: ffeeddccbbaa99887766554433221100");
  EXPECT_EQ(r.ReadStringAttribute("/", "provenance"), SampleProvenance().Hash());

  const Array<double> w = r.ReadDoubles("waypoints", 2);
  EXPECT_EQ(w.dims, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(w.data, (std::vector<double>{1.0, 2.0, 3.0, 4.5, -5.0, 6.25}));
  EXPECT_EQ(r.ReadStringAttribute("waypoints", "units"), "m");

  const Array<float> f = r.ReadFloats("floats", 1);
  EXPECT_EQ(f.dims, (std::vector<std::size_t>{4}));
  EXPECT_EQ(f.data, (std::vector<float>{0.5f, 1.5f, -2.5f, 3.0f}));

  const Array<std::int64_t> it = r.ReadInts("stats/iterations", 0);
  EXPECT_TRUE(it.dims.empty());
  EXPECT_EQ(it.data, (std::vector<std::int64_t>{42}));
  EXPECT_EQ(r.ReadDoubles("stats/time_s").data, (std::vector<double>{0.125}));

  const Array<std::uint8_t> b = r.ReadBytes("deep/er/bytes", 3);
  EXPECT_EQ(b.dims, (std::vector<std::size_t>{2, 2, 2}));
  EXPECT_EQ(b.data, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 255}));

  const Array<double> large = r.ReadDoubles("large");
  EXPECT_EQ(large.dims, (std::vector<std::size_t>{30000, 3}));
  EXPECT_EQ(large.data, LargeDoubles());
  EXPECT_LT(fs::file_size(path), 720000u / 2) << "large dataset should be compressed";

  const Array<double> empty = r.ReadDoubles("empty", 2);
  EXPECT_EQ(empty.dims, (std::vector<std::size_t>{0, 7}));
  EXPECT_TRUE(empty.data.empty());

  EXPECT_EQ(r.ReadStringAttribute("", "planner"), "rrt-connect");
  EXPECT_EQ(r.ReadDoubleAttribute("", "scale"), 2.5);
  EXPECT_EQ(r.ReadIntAttribute("stats", "count"), -7);
  // int64 -> double may lose precision, so it is refused even for small values.
  ExpectInputError([&] { r.ReadDoubleAttribute("stats", "count"); },
                   "attribute 'count' on 'stats' has type int64 (expected a type convertible to float64");
}

TEST_F(ArtifactTest, HasChecksEveryComponent) {
  const fs::path path = dir_ / "a.h5";
  WriteSample(path);
  ArtifactReader r(path, kSchema, 1);
  EXPECT_TRUE(r.Has("waypoints"));
  EXPECT_TRUE(r.Has("stats"));
  EXPECT_TRUE(r.Has("stats/iterations"));
  EXPECT_TRUE(r.Has("/stats/iterations"));
  EXPECT_TRUE(r.Has("deep/er/bytes"));
  EXPECT_FALSE(r.Has("nothing"));
  EXPECT_FALSE(r.Has("nothing/at/all"));
  EXPECT_FALSE(r.Has("stats/nothing"));
  EXPECT_FALSE(r.Has("waypoints/x"));
  EXPECT_FALSE(r.Has("stats//iterations"));
}

TEST_F(ArtifactTest, LargeDatasetsAreChunkedAndCompressed) {
  const fs::path path = dir_ / "a.h5";
  WriteSample(path);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* name : {"large", "waypoints"}) {
    const hid_t ds = H5Dopen2(file, name, H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    const hid_t dcpl = H5Dget_create_plist(ds);
    const bool large = std::strcmp(name, "large") == 0;
    EXPECT_EQ(H5Pget_layout(dcpl), large ? H5D_CHUNKED : H5D_CONTIGUOUS) << name;
    EXPECT_EQ(H5Pget_nfilters(dcpl), large ? 2 : 0) << name;
    H5Pclose(dcpl);
    H5Dclose(ds);
  }
  H5Fclose(file);
}

TEST_F(ArtifactTest, ProvenanceHash) {
  const Provenance base = SampleProvenance();
  const std::string h = base.Hash();
  EXPECT_EQ(h.size(), 32u);
  EXPECT_EQ(h, SampleProvenance().Hash());

  std::vector<Provenance> variants(8, base);
  variants[0].producer = "ausbau-other";
  variants[1].producer_version = "0.1.1";
  variants[2].parameters_yaml = "seed: 2\nrange: 0.5\n";
  variants[3].inputs[0].first = "scene2";
  variants[4].inputs[1].second[0] = 'e';
  variants[5].inputs.emplace_back("extra", "0123");
  variants[6].inputs.pop_back();
  std::swap(variants[7].inputs[0], variants[7].inputs[1]);
  std::vector<std::string> hashes = {h};
  for (const Provenance& v : variants) {
    const std::string hv = v.Hash();
    for (const std::string& other : hashes) EXPECT_NE(hv, other);
    hashes.push_back(hv);
  }

  // Field boundaries matter: moving text from one field to the next changes it.
  Provenance a, b;
  a.producer = "ab";
  a.producer_version = "c";
  b.producer = "a";
  b.producer_version = "bc";
  EXPECT_NE(a.Hash(), b.Hash());
}

TEST_F(ArtifactTest, IdenticalContentGivesIdenticalBytes) {
  WriteSample(dir_ / "first.h5");
  // Later in time (time stamps have one-second resolution) and with the heap
  // full of garbage, so that uninitialized bytes or clocks would show.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  volatile unsigned sink = 0;
  for (int i = 0; i < 64; ++i) {
    std::vector<unsigned char> junk(1024 * (i + 1), static_cast<unsigned char>(0xA5 + i));
    sink = sink + junk[static_cast<std::size_t>(i)];
  }
  WriteSample(dir_ / "sub" / "second.h5");
  const std::string first = ReadAll(dir_ / "first.h5");
  const std::string second = ReadAll(dir_ / "sub" / "second.h5");
  ASSERT_FALSE(first.empty());
  EXPECT_TRUE(first == second) << "files of identical content differ";

  Provenance other = SampleProvenance();
  other.parameters_yaml = "seed: 3\n";
  WriteSample(dir_ / "third.h5", other);
  EXPECT_FALSE(first == ReadAll(dir_ / "third.h5"));
}

// --- rejections --------------------------------------------------------------

TEST_F(ArtifactTest, RejectsMissingFile) {
  const fs::path path = dir_ / "missing.h5";
  ExpectInputError([&] { ArtifactReader r(path, kSchema, 1); }, path.string() + ": file not found");
}

TEST_F(ArtifactTest, RejectsNonHdf5File) {
  const fs::path path = dir_ / "text.h5";
  std::ofstream(path) << "this is not an HDF5 file\n";
  ExpectInputError([&] { ArtifactReader r(path, kSchema, 1); },
                   path.string() + ": not a readable HDF5 file (truncated or corrupt?)");
}

TEST_F(ArtifactTest, RejectsTruncatedFile) {
  const fs::path path = dir_ / "truncated.h5";
  WriteSample(path);
  fs::resize_file(path, fs::file_size(path) / 2);
  ExpectInputError([&] { ArtifactReader r(path, kSchema, 1); },
                   path.string() + ": not a readable HDF5 file (truncated or corrupt?)");
}

TEST_F(ArtifactTest, RejectsDirectory) {
  ExpectInputError([&] { ArtifactReader r(dir_, kSchema, 1); }, dir_.string() + ": is a directory");
}

TEST_F(ArtifactTest, RejectsWrongSchema) {
  const fs::path path = dir_ / "labels.h5";
  WriteSample(path, SampleProvenance(), "ausbau-labels", 1);
  ExpectInputError([&] { ArtifactReader r(path, "ausbau-path", 1); },
                   path.string() + ": wrong schema (expected ausbau-path, got ausbau-labels)");
}

TEST_F(ArtifactTest, RejectsWrongVersion) {
  const fs::path path = dir_ / "v2.h5";
  WriteSample(path, SampleProvenance(), kSchema, 2);
  ExpectInputError([&] { ArtifactReader r(path, kSchema, 1); },
                   path.string() + ": unsupported schema version (expected 1, got 2)");
  ArtifactReader ok(path, kSchema, 2);
}

TEST_F(ArtifactTest, RejectsMissingRootAttribute) {
  const fs::path path = dir_ / "plain.h5";
  {
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    H5Fclose(file);
  }
  ExpectInputError([&] { ArtifactReader r(path, kSchema, 1); }, path.string() + ": missing root attribute 'schema'");
}

TEST_F(ArtifactTest, RejectsWrongAttributeType) {
  const fs::path path = dir_ / "a.h5";
  WriteSample(path);
  ArtifactReader r(path, kSchema, 1);
  ExpectInputError([&] { r.ReadStringAttribute("", "scale"); },
                   "root attribute 'scale' has type float64 (expected string)");
  ExpectInputError([&] { r.ReadIntAttribute("", "scale"); }, "root attribute 'scale' has type float64");
  ExpectInputError([&] { r.ReadIntAttribute("", "nothing"); }, "missing root attribute 'nothing'");
  ExpectInputError([&] { r.ReadIntAttribute("waypoints", "nothing"); }, "missing attribute 'nothing' on 'waypoints'");
  ExpectInputError([&] { r.ReadIntAttribute("nowhere", "units"); }, "missing object 'nowhere'");
}

TEST_F(ArtifactTest, RejectsMissingDataset) {
  const fs::path path = dir_ / "a.h5";
  WriteSample(path);
  ArtifactReader r(path, kSchema, 1);
  ExpectInputError([&] { r.ReadInts("stats/nodes"); }, path.string() + ": missing dataset 'stats/nodes'");
  ExpectInputError([&] { r.ReadInts("nothing/iterations"); }, "missing dataset 'nothing/iterations'");
  ExpectInputError([&] { r.ReadInts("stats"); }, "'stats' is not a dataset");
}

TEST_F(ArtifactTest, RejectsWrongRank) {
  const fs::path path = dir_ / "a.h5";
  WriteSample(path);
  ArtifactReader r(path, kSchema, 1);
  ExpectInputError([&] { r.ReadFloats("floats", 2); }, path.string() + ": dataset 'floats' has rank 1 (expected 2)");
  ExpectInputError([&] { r.ReadInts("stats/iterations", 1); }, "dataset 'stats/iterations' has rank 0 (expected 1)");
}

TEST_F(ArtifactTest, RejectsLossyConversions) {
  const fs::path path = dir_ / "a.h5";
  WriteSample(path);
  ArtifactReader r(path, kSchema, 1);
  ExpectInputError([&] { r.ReadInts("waypoints"); },
                   path.string() + ": dataset 'waypoints' has type float64 (expected a type convertible to int64");
  ExpectInputError([&] { r.ReadFloats("waypoints"); }, "dataset 'waypoints' has type float64");
  ExpectInputError([&] { r.ReadDoubles("stats/iterations"); }, "dataset 'stats/iterations' has type int64");
  ExpectInputError([&] { r.ReadBytes("stats/iterations"); }, "dataset 'stats/iterations' has type int64");
  ExpectInputError([&] { r.ReadBytes("floats"); }, "dataset 'floats' has type float32");
  // Widening conversions are fine.
  EXPECT_EQ(r.ReadDoubles("floats").data, (std::vector<double>{0.5, 1.5, -2.5, 3.0}));
  EXPECT_EQ(r.ReadInts("deep/er/bytes").data.back(), 255);
  EXPECT_EQ(r.ReadFloats("deep/er/bytes").data.back(), 255.0f);
  EXPECT_EQ(r.ReadDoubles("deep/er/bytes").data.front(), 1.0);
}

TEST_F(ArtifactTest, FailuresPrintNothing) {
  const fs::path path = dir_ / "text.h5";
  std::ofstream(path) << "garbage";
  ::testing::internal::CaptureStderr();
  EXPECT_THROW(ArtifactReader(path, kSchema, 1), InputError);
  WriteSample(dir_ / "a.h5");
  {
    ArtifactReader r(dir_ / "a.h5", kSchema, 1);
    EXPECT_THROW(r.ReadInts("missing/x"), InputError);
    EXPECT_THROW(r.ReadInts("waypoints"), InputError);
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

// --- writing -------------------------------------------------------------------

TEST_F(ArtifactTest, UncommittedWriterLeavesNothing) {
  const fs::path path = dir_ / "out" / "a.h5";
  {
    ArtifactWriter w(path, kSchema, 1, SampleProvenance());
    w.WriteDoubles("x", {1, 2, 3}, {3});
    EXPECT_FALSE(fs::exists(path));
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir_ / "out"));
}

TEST_F(ArtifactTest, CommitReplacesExistingTarget) {
  const fs::path path = dir_ / "a.h5";
  Provenance old = SampleProvenance();
  old.parameters_yaml = "old: 1\n";
  WriteSample(path, old);
  {
    Provenance fresh = SampleProvenance();
    fresh.parameters_yaml = "new: 1\n";
    ArtifactWriter w(path, kSchema, 1, fresh);
    w.WriteInts("n", {5}, {});
    // Until Commit() the old file stays readable and unchanged.
    EXPECT_EQ(ArtifactReader(path, kSchema, 1).parameters_yaml(), "old: 1\n");
    EXPECT_EQ(DirEntries().size(), 2u);
    w.Commit();
  }
  ArtifactReader r(path, kSchema, 1);
  EXPECT_EQ(r.parameters_yaml(), "new: 1\n");
  EXPECT_EQ(r.ReadInts("n").data, (std::vector<std::int64_t>{5}));
  EXPECT_FALSE(r.Has("waypoints"));
  EXPECT_EQ(DirEntries(), (std::vector<std::string>{"a.h5"}));
}

TEST_F(ArtifactTest, WriteFailuresAreRuntimeErrorsNamingThePath) {
  std::ofstream(dir_ / "file") << "x";
  const fs::path bad = dir_ / "file" / "a.h5";  // parent is a regular file
  try {
    ArtifactWriter w(bad, kSchema, 1, SampleProvenance());
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    ADD_FAILURE() << "write failure must not be an InputError: " << e.what();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
  }

  const fs::path path = dir_ / "a.h5";
  ArtifactWriter w(path, kSchema, 1, SampleProvenance());
  w.WriteDoubles("x", {1}, {1});
  EXPECT_THROW(w.WriteDoubles("x", {1}, {1}), std::runtime_error);        // exists already
  EXPECT_THROW(w.WriteDoubles("y", {1, 2}, {3}), std::logic_error);       // dims mismatch
  EXPECT_THROW(w.SetAttribute("nowhere", "a", 1.0), std::runtime_error);  // no such object
  EXPECT_THROW(w.SetAttribute("", "provenance", std::string("x")), std::logic_error);
  w.SetAttribute("x", "units", std::string("m"));
  w.SetAttribute("x", "units", std::string("mm"));  // replaces
  w.Commit();
  EXPECT_THROW(w.WriteDoubles("z", {1}, {1}), std::logic_error);
  EXPECT_EQ(ArtifactReader(path, kSchema, 1).ReadStringAttribute("x", "units"), "mm");

  // A directory as the target is refused before anything is written (an
  // output is never a directory, core/atomic_file.h); no temporary file.
  fs::create_directories(dir_ / "isdir" / "child");
  EXPECT_THROW(ArtifactWriter(dir_ / "isdir", kSchema, 1, SampleProvenance()), InputError);
  EXPECT_EQ(DirEntries(), (std::vector<std::string>{"a.h5", "file", "isdir"}));
}

TEST_F(ArtifactTest, EmptyInputsAndStrings) {
  const fs::path path = dir_ / "a.h5";
  {
    ArtifactWriter w(path, kSchema, 1, Provenance{});
    w.SetAttribute("", "empty", std::string());
    w.Commit();
  }
  ArtifactReader r(path, kSchema, 1);
  EXPECT_EQ(r.producer(), "");
  EXPECT_EQ(r.parameters_yaml(), "");
  EXPECT_EQ(r.ReadStringAttribute("", "inputs"), "{}");
  EXPECT_EQ(r.ReadStringAttribute("", "empty"), "");
  EXPECT_EQ(r.provenance_hash(), Provenance{}.Hash());
}

TEST_F(ArtifactTest, ReadsVariableLengthStrings) {
  // As h5py writes them: variable-length UTF-8.
  const fs::path path = dir_ / "vlen.h5";
  {
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    const hid_t space = H5Screate(H5S_SCALAR);
    for (const char* name : {"schema", "producer", "parameters", "provenance"}) {
      const char* value = std::strcmp(name, "schema") == 0 ? kSchema : "v";
      const hid_t attr = H5Acreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
      H5Awrite(attr, type, &value);
      H5Aclose(attr);
    }
    const std::int32_t version = 1;  // int32 converts to int64 without loss
    const hid_t attr = H5Acreate2(file, "schema_version", H5T_STD_I32BE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attr, H5T_NATIVE_INT32, &version);
    H5Aclose(attr);
    H5Sclose(space);
    H5Tclose(type);
    H5Fclose(file);
  }
  ArtifactReader r(path, kSchema, 1);
  EXPECT_EQ(r.provenance_hash(), "v");
  EXPECT_EQ(r.ReadStringAttribute("", "schema"), kSchema);
}

// --- ExistingProvenanceHash -----------------------------------------------------

TEST_F(ArtifactTest, ExistingProvenanceHash) {
  const fs::path good = dir_ / "good.h5";
  WriteSample(good);
  EXPECT_EQ(ExistingProvenanceHash(good, kSchema, 1), SampleProvenance().Hash());
  EXPECT_EQ(ExistingProvenanceHash(good, "ausbau-other", 1), std::nullopt);
  EXPECT_EQ(ExistingProvenanceHash(good, kSchema, 2), std::nullopt);
  EXPECT_EQ(ExistingProvenanceHash(dir_ / "missing.h5", kSchema, 1), std::nullopt);
  EXPECT_EQ(ExistingProvenanceHash(dir_, kSchema, 1), std::nullopt);

  const fs::path text = dir_ / "text.h5";
  std::ofstream(text) << "not hdf5";
  EXPECT_EQ(ExistingProvenanceHash(text, kSchema, 1), std::nullopt);

  const fs::path truncated = dir_ / "truncated.h5";
  WriteSample(truncated);
  fs::resize_file(truncated, fs::file_size(truncated) / 2);
  EXPECT_EQ(ExistingProvenanceHash(truncated, kSchema, 1), std::nullopt);

  const fs::path empty = dir_ / "empty.h5";
  std::ofstream(empty).flush();
  EXPECT_EQ(ExistingProvenanceHash(empty, kSchema, 1), std::nullopt);
}

}  // namespace
}  // namespace ausbau
