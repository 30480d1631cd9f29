#!/usr/bin/env bash
# Runs each libFuzzer harness for a given time and prints one line per
# harness: executions, wall and CPU seconds, rates, findings and where they
# were written.
#   fuzz/run.sh <build dir> <seconds per harness> [harness ...]
# (`make fuzz` calls it; default: every harness.) Each harness grows its own
# corpus in <build>/fuzz-out/<harness>/corpus from the seeds in
# fuzz/corpus/<harness>/; findings (crash-*, leak-*, timeout-*, oom-*) go to
# <build>/fuzz-out/<harness>/findings/. Exit status 1 when any harness has a
# finding. FUZZ_RUNS=<n> (environment) also stops each harness after n
# executions, e.g. FUZZ_RUNS=1000000 with a generous time: the target of
# 10^6 executions, whatever the machine's load.
set -uo pipefail
build=${1:?usage: fuzz/run.sh <build dir> <seconds> [harness ...]}
seconds=${2:?usage: fuzz/run.sh <build dir> <seconds> [harness ...]}
shift 2
source_dir=$(cd "$(dirname "$0")/.." && pwd)
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(scene mesh path_csv artifact path tau voxels spheres labels distfield)

# A small quarantine: HDF5 and assimp allocate megabytes per run, and with
# ASan's default 256 MB quarantine every run maps fresh pages (4x slower).
export ASAN_OPTIONS="quarantine_size_mb=16:max_malloc_fill_size=0:${ASAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$source_dir/fuzz/lsan.supp:${LSAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:${UBSAN_OPTIONS:-}"

status=0
summary=()
for h in "${harnesses[@]}"; do
  exe="$build/bin/fuzz_$h"
  if [ ! -x "$exe" ]; then echo "fuzz: no harness $exe" >&2; exit 2; fi
  out="$build/fuzz-out/$h"
  mkdir -p "$out/corpus" "$out/findings"
  log="$out/fuzz.log"
  echo "fuzz: $h for ${seconds} s (log $log)"
  # -timeout: one input running 10 s is a hang; -rss/-malloc_limit_mb: an
  # allocation over 2 GB is a finding. The files under test go to a folder
  # of this process (fuzz_util.h: AUSBAU_FUZZ_TMP, /dev/shm or the temp folder).
  # The CPU seconds the harness got (user + system) beside the wall time:
  # on a shared machine the rate per CPU second is what the harness costs.
  runs_flag=()
  [ -z "${FUZZ_RUNS:-}" ] || runs_flag=(-runs="$FUZZ_RUNS")
  start=$(date +%s)
  TIMEFORMAT='%U %S'
  { time "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 \
    "${runs_flag[@]}" -artifact_prefix="$out/findings/" "$out/corpus" "$source_dir/fuzz/corpus/$h" > "$log" 2>&1; } 2> "$out/cpu"
  rc=$?
  elapsed=$(( $(date +%s) - start ))
  cpu=$(awk '{printf "%.0f", $1 + $2}' "$out/cpu" 2>/dev/null)
  runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | awk '{print $2}')
  findings=$(find "$out/findings" -type f | wc -l)
  [ "$rc" -eq 0 ] && [ "$findings" -eq 0 ] || status=1
  rate=$(awk -v n="${runs:-0}" -v s="$elapsed" -v c="${cpu:-0}" \
    'BEGIN { printf "%7.0f/s %7.0f/CPU-s", n / (s > 0 ? s : 1), n / (c > 0 ? c : 1) }')
  load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null)
  line=$(printf '%-10s %12s executions %6s s (%5s CPU-s) %s %3s findings, load %s' "$h" "${runs:-?}" "$elapsed" \
    "${cpu:-?}" "$rate" "$findings" "${load:-?}")
  [ "$findings" -eq 0 ] || line="$line in $out/findings/"
  [ "$rc" -eq 0 ] || [ "$findings" -gt 0 ] || line="$line (exit $rc, see $log)"
  summary+=("$line")
done
echo
echo "fuzz: summary (harness, executions, wall and CPU seconds, executions per wall and per CPU second, findings)"
printf '  %s\n' "${summary[@]}"
exit $status
