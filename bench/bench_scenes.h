// What ausbau-farr-bench and ausbau-collision-bench share: a scene named on
// the command line resolved to its scene.yaml, the poses a planner checks
// recorded with their answers, those poses timed through a check in chunks,
// and whether two plans returned the same path (the check that a faster
// collision check changed only the time).
#pragma once

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "collision/validity.h"
#include "fixtures/flange.h"
#include "planning/planner.h"

namespace ausbau::bench {

// OMPL.app scenes by name (../shared/benchmarks/ompl/<name>.yaml, beside the
// source tree; AUSBAU_SOURCE_DIR overrides the source dir compiled in),
// parasol-flange-1.0 (../shared/benchmarks/parasol/flange-1.0/), and
// flange-<scale> generated into out_dir/scenes (fixtures/flange.h). An
// empty path, with the reason in *skipped, where the file is not there.
inline std::filesystem::path BenchSceneFile(const std::string& name, const std::filesystem::path& out_dir,
                                            std::string* skipped) {
  namespace fs = std::filesystem;
  const char* source = std::getenv("AUSBAU_SOURCE_DIR");
  const fs::path root = source ? fs::path(source) : fs::path(AUSBAU_SOURCE_DIR);
  if (name.rfind("flange-", 0) == 0) {
    const double scale = std::atof(name.c_str() + 7);
    return GenerateFlangeScene(scale, out_dir / "scenes" / name);
  }
  fs::path path = name == "parasol-flange-1.0"
                      ? root / ".." / "shared" / "benchmarks" / "parasol" / "flange-1.0" / "flange-1.0.yaml"
                      : root / ".." / "shared" / "benchmarks" / "ompl" / (name + ".yaml");
  if (!fs::exists(path)) {
    *skipped = "not present (" + path.string() + ")";
    return {};
  }
  return path;
}

// Both solved or both not, with bit-identical waypoints.
inline bool SamePath(const PlanResult& a, const PlanResult& b) {
  if (a.solved() != b.solved() || a.path.size() != b.path.size()) return false;
  for (std::size_t i = 0; i < a.path.size(); ++i) {
    if (a.path[i].t != b.path[i].t || a.path[i].q.coeffs() != b.path[i].q.coeffs()) return false;
  }
  return true;
}

// Records every pose the planner checks, with the inner checker's answer.
class RecordingValidity : public PoseValidity {
 public:
  explicit RecordingValidity(const PoseValidity& inner) : inner_(inner) {}
  mutable std::vector<Pose> poses;
  mutable std::vector<char> invalid;

 protected:
  bool CheckValid(const Pose& pose) const override {
    const bool valid = inner_.IsValid(pose);
    std::lock_guard<std::mutex> lock(mutex_);
    poses.push_back(pose);
    invalid.push_back(!valid);
    return valid;
  }

 private:
  const PoseValidity& inner_;
  mutable std::mutex mutex_;
};

// Times `check` over poses[indices] in chunks interleaved with the other
// methods by the caller.
template <typename Check>
inline double TimeChunk(const std::vector<Pose>& poses, const std::vector<std::size_t>& indices, std::size_t begin,
                        std::size_t end, Check&& check) {
  int sink = 0;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = begin; i < end; ++i) sink += check(poses[indices[i]]);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (sink < 0) std::printf(" ");  // keep the calls
  return s;
}

}  // namespace ausbau::bench
