#include "geometry/weld.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>

namespace ausbau {
namespace {

// A position as the key of a hash map. -0 is stored as +0, so that equal
// positions (== per coordinate) have equal bits and so equal hashes.
struct PositionKey {
  std::array<double, 3> xyz;
  bool operator==(const PositionKey& other) const {
    return xyz[0] == other.xyz[0] && xyz[1] == other.xyz[1] && xyz[2] == other.xyz[2];
  }
};

struct PositionKeyHash {
  std::size_t operator()(const PositionKey& key) const {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the coordinates' bits
    for (double x : key.xyz) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
      h ^= h >> 29;
    }
    return static_cast<std::size_t>(h);
  }
};

PositionKey KeyOf(const Eigen::Vector3d& p) {
  PositionKey key;
  for (int k = 0; k < 3; ++k) key.xyz[k] = p[k] == 0.0 ? 0.0 : p[k];
  return key;
}

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

}  // namespace

std::vector<int> WeldExactPositions(const std::vector<Eigen::Vector3d>& vertices) {
  std::unordered_map<PositionKey, int, PositionKeyHash> ids;
  ids.reserve(vertices.size());
  std::vector<int> welded(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    welded[i] = ids.emplace(KeyOf(vertices[i]), static_cast<int>(ids.size())).first->second;
  }
  return welded;
}

std::vector<int> WeldWithinTolerance(const std::vector<Eigen::Vector3d>& vertices, double tolerance,
                                     WeldDistance distance, const Eigen::Vector3d& grid_origin, double cell_size,
                                     std::vector<Eigen::Vector3d>* welded) {
  const double tolerance_squared = tolerance * tolerance;
  const auto within = [&](const Eigen::Vector3d& representative, const Eigen::Vector3d& p) {
    if (distance == WeldDistance::kEuclidean) return (representative - p).squaredNorm() <= tolerance_squared;
    return (representative - p).cwiseAbs().maxCoeff() <= tolerance;
  };
  std::unordered_map<CellKey, std::vector<int>, CellKeyHash> grid;
  grid.reserve(vertices.size());
  std::vector<int> map(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3d& p = vertices[i];
    CellKey home;
    std::int64_t* home_coordinates[3] = {&home.x, &home.y, &home.z};
    for (int k = 0; k < 3; ++k) {
      *home_coordinates[k] = static_cast<std::int64_t>(std::floor((p[k] - grid_origin[k]) / cell_size));
    }
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = grid.find({home.x + dx, home.y + dy, home.z + dz});
          if (it == grid.end()) continue;
          for (int w : it->second) {
            if (within((*welded)[w], p)) {
              found = w;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int>(welded->size());
      welded->push_back(p);
      grid[home].push_back(found);
    }
    map[i] = found;
  }
  return map;
}

}  // namespace ausbau
