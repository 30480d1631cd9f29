// The machine a benchmark ran on, for its summary: CPU, cores, memory,
// compiler, FCL, host, date and load (the development machine is shared, so
// the load average is part of every result).
#pragma once

#include <string>

namespace ausbau::bench {

struct MachineInfo {
  std::string cpu;       // /proc/cpuinfo "model name"
  int cores = 0;         // logical cores
  double ram_gib = 0;    // /proc/meminfo MemTotal
  std::string compiler;  // "GCC 12.2.0"
  std::string ompl;      // "1.5.2" or "" when built without OMPL (set by ausbau-bench)
  std::string fcl;       // FCL_VERSION
  std::string host;
  std::string date_utc;    // ISO 8601
  std::string load_start;  // /proc/loadavg when described
};
MachineInfo DescribeMachine();
// "CPU, N logical cores, X GiB RAM; compiler; FCL v".
std::string MachineLine(const MachineInfo& machine);
std::string LoadAverage();  // "a b c" from /proc/loadavg, or "unknown"
std::string NowIsoUtc();    // 2026-11-22T12:34:56Z

}  // namespace ausbau::bench
