// libFuzzer harness of the scene reader (LoadScene, common/scene/scene.cpp):
// the input is scene.yaml, in a folder that also holds the same small valid
// tetrahedron as s.obj, d.obj, s.off and d.off for the scene to name. Most
// seeds name the OFF files: assimp's OBJ importer allocates and fills a
// 16 MB buffer per file, about 80 ms under ASan, against 1-2 ms for OFF
// (the mesh formats themselves are fuzz_mesh's subject); one seed names the
// OBJ files, which an input may name as well.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ausbau::fuzz;
  static const std::filesystem::path dir = [] {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    const std::string off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    for (const char* name : {"s.obj", "d.obj", "s.off", "d.off"}) {
      const std::string& text = std::string(name).back() == 'j' ? obj : off;
      WriteBytes(WorkDir() / name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
    }
    return WorkDir();
  }();
  const std::filesystem::path file = dir / "scene.yaml";
  WriteBytes(file, data, size);
  ExpectOnlyInputErrors([&] { ausbau::LoadScene(file); });
  return 0;
}
