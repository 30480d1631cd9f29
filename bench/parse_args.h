// Command-line parsing for the benchmarks, with the stages' exit codes
// (cli/stage_main.h): --help and --version exit 0, a bad flag or value
// prints CLI11's message and exits 2 (CLI11's own codes are 100+).
#pragma once

#include <CLI/CLI.hpp>

namespace ausbau::bench {

// -1: parsed, go on; otherwise the exit code to return from main.
inline int ParseArguments(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? 0 : 2;
  }
  return -1;
}

}  // namespace ausbau::bench
