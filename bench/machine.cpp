#include "machine.h"

#include <fcl/config.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <thread>

namespace ausbau::bench {
namespace {

// The value after "key:" on the first line of `file` starting with key.
std::string ReadFirstField(const char* file, const std::string& key) {
  FILE* f = std::fopen(file, "r");
  if (!f) return "";
  char line[1024];
  std::string value;
  while (std::fgets(line, sizeof(line), f)) {
    std::string text(line);
    if (text.compare(0, key.size(), key) != 0) continue;
    const auto colon = text.find(':');
    if (colon == std::string::npos) continue;
    value = text.substr(colon + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    while (!value.empty() && (value.back() == '\n' || value.back() == ' ')) value.pop_back();
    break;
  }
  std::fclose(f);
  return value;
}

}  // namespace

std::string LoadAverage() {
  FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return "unknown";
  double a = 0, b = 0, c = 0;
  const int n = std::fscanf(f, "%lf %lf %lf", &a, &b, &c);
  std::fclose(f);
  if (n != 3) return "unknown";
  char text[64];
  std::snprintf(text, sizeof text, "%.2f %.2f %.2f", a, b, c);
  return text;
}

std::string NowIsoUtc() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[64];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

MachineInfo DescribeMachine() {
  MachineInfo m;
  m.cpu = ReadFirstField("/proc/cpuinfo", "model name");
  if (m.cpu.empty()) m.cpu = "unknown CPU";
  m.cores = static_cast<int>(std::thread::hardware_concurrency());
  const std::string mem = ReadFirstField("/proc/meminfo", "MemTotal");  // "24576000 kB"
  m.ram_gib = mem.empty() ? 0.0 : std::atof(mem.c_str()) / (1024.0 * 1024.0);
#if defined(__clang__)
  m.compiler = std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  m.compiler = std::string("GCC ") + __VERSION__;
#else
  m.compiler = __VERSION__;
#endif
  m.fcl = FCL_VERSION;
  char host[256] = {0};
  if (gethostname(host, sizeof(host) - 1) == 0) m.host = host;
  if (m.host.empty()) m.host = "UNKNOWN";
  m.date_utc = NowIsoUtc();
  m.load_start = LoadAverage();
  return m;
}

std::string MachineLine(const MachineInfo& m) {
  char text[512];
  std::snprintf(text, sizeof text, "%s, %d logical cores, %.1f GiB RAM; %s; FCL %s", m.cpu.c_str(), m.cores, m.ram_gib,
                m.compiler.c_str(), m.fcl.c_str());
  return text;
}

}  // namespace ausbau::bench
