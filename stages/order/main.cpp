// ausbau-order: the order in which an assembly comes apart, part by part,
// and for each part that does not come out, what blocks it. The work is
// workflow/disassembly_order.h; see README.md beside this file.
#include <cstdio>

#include "cli/stage.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/log.h"
#include "workflow/disassembly_order.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// No artifact of the runner's and no scene: the parts are files, and the
// answer (order.json, a scene and path.h5 per attempt) a folder written anew.
constexpr StageSpec kOrderStage{
    "ausbau-order",
    "Finds the order in which an assembly comes apart, and what blocks each part that does not.",
    SceneHash::kNoScene,
    {},
    {},
    "accepted for a pipeline's sake: the order is always found anew"};

struct OrderStageOptions {
  std::vector<std::string> parts, fixed;
  std::string parts_dir, output = "order";
  DisassemblyOrderOptions order;
};

void DeclareOrder(StageDefinition& stage, OrderStageOptions* options) {
  stage.Option("--part", &options->parts, "a part: NAME=FILE, or FILE (named by its stem); repeat for each part",
               CacheKey::kYes);
  // The parts' files are inputs: no output may replace one.
  stage.InputPaths("--part", [options] {
    std::vector<std::string> files;
    for (const std::string& part : options->parts) files.push_back(part.substr(part.find('=') + 1));
    return files;
  });
  stage.Option("--parts-dir", &options->parts_dir, "every mesh file in this folder is a part, named by its stem",
               CacheKey::kYes);
  stage.Option("--fixed", &options->fixed, "a part that stays in (the frame): S in every round, never taken out",
               CacheKey::kYes);
  DisassemblyOrderOptions& order = options->order;
  stage
      .Option("--part-budget", &order.part_budget_s, "seconds each attempt (one part, one round) may take",
              CacheKey::kNo)
      ->check(Within(1e-3, 7 * 24 * 3600.0));
  stage.Option("--units", &order.units, "the parts' length unit: mm, cm, m or inch (in)", CacheKey::kYes)
      ->check(CLI::IsMember({"mm", "cm", "m", "inch", "in"}));
  stage.Option("--rigid-tolerance", &order.plan.volume.rigid_tolerance_mm,
               "mm (converted by the scene's units): how deep a rigid solid of D may touch into S", CacheKey::kYes);
  stage.Seed(&order.plan.planner.seed, "random seed; the same seed gives the same output");
  stage.OutputFolder("--output-dir", &options->output, "output folder: order.json and round-<r>/<part>/");
  // The parts as the work will take them (--parts-dir a folder, --fixed
  // naming a part): also checked by --validate.
  stage.CheckOptions([options] { CollectAssemblyParts(options->parts, options->parts_dir, options->fixed); });
}

void PrintOrder(const DisassemblyOrder& order, const fs::path& json) {
  std::printf("%s\n", order.complete ? "ORDER FOUND" : "NO ORDER EXISTS");
  for (std::size_t i = 0; i < order.steps.size(); ++i) {
    std::printf("  step %zu:", i + 1);
    for (const std::string& name : order.steps[i]) std::printf(" %s", TerminalSafe(name).c_str());
    std::printf("\n");
  }
  for (const PartAttempt& a : order.attempts) {
    if (a.removable) continue;
    std::printf("  round %d: %s %s", a.round, TerminalSafe(a.part).c_str(), a.status_detail.c_str());
    for (std::size_t i = 0; i < a.blocked_by.size(); ++i) {
      std::printf("%s%s", i == 0 ? "; blocked by " : ", ", TerminalSafe(DescribePartContact(a.blocked_by[i])).c_str());
    }
    std::printf("\n");
  }
  if (!order.cycle.empty()) {
    std::printf("  cycle:");
    for (std::size_t i = 0; i < order.cycle.size(); ++i)
      std::printf("%s %s", i > 0 ? " ->" : "", TerminalSafe(order.cycle[i]).c_str());
    std::printf("\n");
  }
  std::printf("  order: %s\n", TerminalSafe(json.string()).c_str());
  std::fflush(stdout);
}

int FindOrder(const StageRun&, const OrderStageOptions& stage_options) {
  DisassemblyOrderOptions options = stage_options.order;
  options.out = stage_options.output;
  options.progress = ShowProgress("parts tried in this round");
  const std::vector<AssemblyPart> assembly =
      CollectAssemblyParts(stage_options.parts, stage_options.parts_dir, stage_options.fixed);
  const DisassemblyOrder order = PlanDisassemblyOrder(assembly, options);
  const fs::path json = fs::path(stage_options.output) / "order.json";
  WriteTextFileAtomically(json, DisassemblyOrderJson(order, options));
  PrintOrder(order, json);
  return order.complete ? kExitOk : kExitNoPath;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kOrderStage, DeclareOrder, FindOrder)
