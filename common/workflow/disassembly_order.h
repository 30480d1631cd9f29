// ausbau-order's work: the order in which an assembly of parts comes apart.
//
// Each round tries every part that is still in, as D, against all the others
// (and the fixed parts) as S: the real planning of ausbau-plan under
// rigid-exact (workflow/plan_scene.h, with a time budget per attempt) and the
// verdict's checks of the result (the exact check of the path, and where it
// fails, the parts that block D at the end of its best partial path:
// FindBlockingParts). The parts removable in a round come out together (the
// round is one step of the sequence; within it, in the order given); the
// next round tries the rest again. When a round frees none, no order exists
// for the parts left: each blocked part points at the part that blocks it
// most (one whose removal alone lets it out along a straight pull, else the
// deepest contact, else the nearest one still in), and following
// these from the first part left ends in a cycle, which is named.
//
// Parts are mesh files, one part per file, already in their assembled
// poses (the world frame). A part picked by name from one assembly file
// (issue 18, item 1) plugs in as one more way of making the AssemblyPart
// list: the rounds only need a name and a mesh file per part.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "collision/part_contacts.h"
#include "core/log.h"
#include "planning/path_io.h"
#include "workflow/plan_scene.h"

namespace ausbau {

struct AssemblyPart {
  std::string name;  // unique; names the part in order.json and blocked_by
  std::filesystem::path file;
  bool fixed = false;  // stays in (the frame): part of S in every round, never tried
};

struct DisassemblyOrderOptions {
  PlanSceneOptions plan;      // validity rigid-exact; the planner, seed and time limit
  double part_budget_s = 10;  // seconds per attempt (the planner gets 3/4 of it)
  std::string units = "mm";   // the scenes' units (the rigid tolerance is in mm)
  std::filesystem::path out;  // round-<r>/<part>/: scene.yaml, path.h5, path.csv
  // The parts tried in this round of those to try (core/log.h): a new
  // count each round; empty = silent.
  ProgressCallback progress;
  void Check() const;  // throws InputError naming the flag
};

struct PartAttempt {
  int round = 0;  // 1-based
  std::string part;
  bool removable = false;
  std::string status_detail;  // as the verdict's (workflow/verdict.h)
  std::string folder;         // where its scene and path are
  std::size_t waypoints = 0;  // of the path, or of the best partial path
  double seconds = 0;
  std::vector<PartContact> blocked_by;  // not removable: named by part
};

struct DisassemblyOrder {
  std::vector<std::vector<std::string>> steps;  // the parts out in each round that freed any
  std::vector<std::string> sequence;            // the steps flattened
  std::vector<std::string> remaining;           // still in at the end (fixed parts not counted)
  std::vector<std::string> fixed;
  std::vector<PartAttempt> attempts;
  bool complete = false;           // every part that is not fixed came out
  std::vector<std::string> cycle;  // not complete: parts blocking each other in a ring (first repeated at the end)
};

// Throws InputError for a part list that does not fit (fewer than two
// parts, a name twice, a missing file, nothing to take out).
// The parts of the command line: every mesh file of `dir` ("" = none),
// sorted, named by its stem; then `given` as NAME=FILE or FILE (named by
// its stem); the parts named in `fixed` marked fixed. Throws InputError naming --parts-dir or
// --fixed.
std::vector<AssemblyPart> CollectAssemblyParts(const std::vector<std::string>& given, const std::string& dir,
                                               const std::vector<std::string>& fixed);

DisassemblyOrder PlanDisassemblyOrder(const std::vector<AssemblyPart>& parts, const DisassemblyOrderOptions& options);

// order.json (documented in stages/order/README.md).
std::string DisassemblyOrderJson(const DisassemblyOrder& order, const DisassemblyOrderOptions& options);

// The cycle of a blocked round: from the first part, follow each part's
// first blocker that is still in (blocked_by lists the parts whose removal
// frees it first, then deepest contact, then nearest) until a part
// repeats. Empty when a part has no such blocker.
std::vector<std::string> FindBlockingCycle(const std::vector<std::string>& remaining,
                                           const std::vector<PartAttempt>& round_attempts);

}  // namespace ausbau
