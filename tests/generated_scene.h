// A generated scene for tests, apart from test_scenes.h because it needs
// the scene generators (ausbau_fixtures): only the tests that link
// ausbau_test_generated_scene pay for them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace ausbau::testing {

// Generates `family` (see fixtures/generators.h) into a fresh folder and
// returns the scene.yaml path.
std::filesystem::path MakeGeneratedScene(const std::string& family, std::uint64_t seed = 1);

}  // namespace ausbau::testing
