// libFuzzer harness of the path CSV reader (ReadPathCsv,
// common/planning/path_io.cpp): the input is the CSV file.
#include <cstdint>

#include "fuzz_util.h"
#include "planning/path_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ausbau::fuzz;
  static const std::filesystem::path file = WorkDir() / "path.csv";
  WriteBytes(file, data, size);
  ExpectOnlyInputErrors([&] { ausbau::ReadPathCsv(file); });
  return 0;
}
