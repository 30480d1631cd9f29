// ausbau-order: the order in which an assembly comes apart, part by part,
// and for each part that does not come out, what blocks it. The work is
// workflow/disassembly_order.h; see README.md beside this file.
#include <cstdio>

#include "cli/stage_main.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "workflow/disassembly_order.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

void PrintOrder(const DisassemblyOrder& order, const fs::path& json) {
  std::printf("%s\n", order.complete ? "ORDER FOUND" : "NO ORDER EXISTS");
  for (std::size_t i = 0; i < order.steps.size(); ++i) {
    std::printf("  step %zu:", i + 1);
    for (const std::string& name : order.steps[i]) std::printf(" %s", name.c_str());
    std::printf("\n");
  }
  for (const PartAttempt& a : order.attempts) {
    if (a.removable) continue;
    std::printf("  round %d: %s %s", a.round, a.part.c_str(), a.status_detail.c_str());
    for (std::size_t i = 0; i < a.blocked_by.size(); ++i) {
      std::printf("%s%s", i == 0 ? "; blocked by " : ", ", DescribePartContact(a.blocked_by[i]).c_str());
    }
    std::printf("\n");
  }
  if (!order.cycle.empty()) {
    std::printf("  cycle:");
    for (std::size_t i = 0; i < order.cycle.size(); ++i)
      std::printf("%s %s", i > 0 ? " ->" : "", order.cycle[i].c_str());
    std::printf("\n");
  }
  std::printf("  order: %s\n", json.string().c_str());
  std::fflush(stdout);
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  std::vector<std::string> parts, fixed;
  std::string parts_dir, output = "order";
  DisassemblyOrderOptions options;
  return RunStage(
      {"ausbau-order", "Finds the order in which an assembly comes apart, and what blocks each part that does not."},
      argc, argv,
      [&](CLI::App& app) {
        app.add_option("--part", parts, "a part: NAME=FILE, or FILE (named by its stem); repeat for each part");
        app.add_option("--parts-dir", parts_dir, "every mesh file in this folder is a part, named by its stem");
        app.add_option("--fixed", fixed, "a part that stays in (the frame): S in every round, never taken out");
        app.add_option("--part-budget", options.part_budget_s, "seconds each attempt (one part, one round) may take")
            ->capture_default_str()
            ->check(Within(1e-3, 7 * 24 * 3600.0));
        app.add_option("--units", options.units, "the parts' length unit: mm, cm, m or inch (in)")
            ->capture_default_str()
            ->check(CLI::IsMember({"mm", "cm", "m", "inch", "in"}));
        app.add_option("--rigid-tolerance", options.plan.volume.rigid_tolerance_mm,
                       "mm (converted by the scene's units): how deep a rigid solid of D may touch into S")
            ->capture_default_str();
        app.add_option("--seed", options.plan.planner.seed, "random seed; the same seed gives the same output")
            ->capture_default_str()
            ->check(NonNegative());
        app.add_option("--output-dir", output, "output folder: order.json and round-<r>/<part>/")
            ->capture_default_str();
      },
      [&] {
        options.out = output;
        const std::vector<AssemblyPart> assembly = CollectAssemblyParts(parts, parts_dir, fixed);
        const DisassemblyOrder order = PlanDisassemblyOrder(assembly, options);
        const fs::path json = fs::path(output) / "order.json";
        WriteTextFileAtomically(json, DisassemblyOrderJson(order, options));
        PrintOrder(order, json);
        return order.complete ? kExitOk : kExitNoPath;
      });
}
