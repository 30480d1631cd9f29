// Small scenes generated in code (meshes + scene.yaml), for the demo and the
// tests. Each is a real planning problem with a known answer.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ausbau {

// Family names: "rod-in-cage", "peg-in-plate", "two-boxes".
std::vector<std::string> GeneratedSceneFamilies();

// Writes <dir>/scene.yaml, <dir>/environment.obj, <dir>/part.obj and returns
// the scene.yaml path. `seed` varies the dimensions a little. Throws
// InputError for an unknown family.
std::filesystem::path GenerateScene(const std::string& family, std::uint64_t seed, const std::filesystem::path& dir);

}  // namespace ausbau
