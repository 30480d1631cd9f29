#!/usr/bin/env bash
# Plans each OMPL.app scene with several seeds and reports success, time and
# the dense re-check (ausbau-plan verifies every path at 1% of D's diagonal).
#   scripts/ompl-scenes.sh [planner] [seeds] [time-limit] [scene ...]
# Needs ../shared/benchmarks/ompl next to the repository and a built tree.
set -uo pipefail
cd "$(dirname "$0")/.."
planner=${1:-cr-rrtc}; seeds=${2:-10}; limit=${3:-60}; shift 3 2>/dev/null || shift $#
scenes=("$@"); [ ${#scenes[@]} -eq 0 ] && scenes=(Easy Apartment alpha-1.5)
bench=../shared/benchmarks/ompl
out=out/ompl-scenes; mkdir -p "$out"
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
printf '%-12s %-8s %5s %10s %10s %10s\n' scene planner seed result time_s checks
for scene in "${scenes[@]}"; do
  for seed in $(seq 1 "$seeds"); do
    log=$(build/bin/ausbau-plan --scene "$bench/$scene.yaml" --planner "$planner" --seed "$seed" \
          --time-limit "$limit" -o "$out/$scene-$seed.h5" --csv "$out/$scene-$seed.csv" --force 2>&1)
    rc=$?
    t=$(echo "$log" | sed -n 's/.* after \([0-9.]*\) s:.*/\1/p')
    c=$(echo "$log" | sed -n 's/.* \([0-9]*\) collision checks/\1/p')
    case $rc in 0) r=solved;; 3) r=no-path;; *) r="error($rc)";; esac
    printf '%-12s %-8s %5s %10s %10s %10s\n' "$scene" "$planner" "$seed" "$r" "$t" "$c"
  done
done
