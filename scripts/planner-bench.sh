#!/bin/bash
# Ours against OMPL's RRT-Connect (make bench-planners, issue 29): the OMPL.app
# scenes and the Parasol flange through ausbau-bench (ausbau-plan as a whole
# process with its default flags, CR-RRTC in process, OMPL default range, side
# by side in one run), plus our own channel families (generated here, random
# world placement, no goal pose, so ours only): panel-channel (a tongue under
# the roof of an L-shaped T-slot, 0.2-1.0 mm clearances), panel-zchannel (a
# Z-shaped one, three legs, 0.2-0.5 mm) and panel-keyhole (slide, turn 90
# degrees, lift; 0.2-0.5 mm), each channel path judged by the external set's
# independent oracle.py.
#
#   scripts/planner-bench.sh BIN OUT RUNS TIME_LIMIT SCENES CHANNEL_SEEDS [RECORDED]
#     BIN            folder of ausbau-bench, ausbau-plan, ausbau-scene-gen
#     OUT            output folder (summary.md, speedups.csv, results.csv,
#                    OMPL logs, ausbau-plan/<scene>-seed<N>.{h5,csv,log},
#                    scenes/<family>-s<N>/, oracle.txt)
#     RUNS           seeds per scene; TIME_LIMIT seconds per run
#     SCENES         comma list for ausbau-bench --scenes (names or yaml paths)
#     CHANNEL_SEEDS  space-separated generator seeds of each channel family
#                    ("" for none); the families: $CHANNEL_FAMILIES, default
#                    "panel-channel panel-zchannel panel-keyhole"
#     RECORDED       speedups.csv to check against (ausbau-bench --recorded);
#                    empty: no check
# Exit 1 when the check fails or an oracle call finds a channel path invalid;
# 2 on bad usage. Needs /usr/bin/python3 with numpy for the oracle (reported,
# not failed, where it is missing).
set -u
[ $# -ge 6 ] || { echo "usage: planner-bench.sh BIN OUT RUNS TIME_LIMIT SCENES CHANNEL_SEEDS [RECORDED]" >&2; exit 2; }
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=$(cd "$1" && pwd) || { echo "planner-bench: no folder $1" >&2; exit 2; }
OUT=$2
RUNS=$3
LIMIT=$4
SCENES=$5
CHANNEL_SEEDS=$6
RECORDED=${7:-}
ORACLE=$HERE/../shared/benchmarks/inistate-external/oracle.py
mkdir -p "$OUT/scenes" || exit 2

CHANNEL_FAMILIES=${CHANNEL_FAMILIES:-panel-channel panel-zchannel panel-keyhole}
channels=()
for family in $CHANNEL_FAMILIES; do
  case "$family" in panel-channel | panel-zchannel | panel-keyhole) ;;
    *) echo "planner-bench: '$family' is not a channel family (panel-channel, panel-zchannel, panel-keyhole)" >&2; exit 2 ;;
  esac
  for seed in $CHANNEL_SEEDS; do
    case "$seed" in '' | *[!0-9]*) echo "planner-bench: channel seed '$seed' is not a number" >&2; exit 2 ;; esac
    dir="$OUT/scenes/$family-s$seed"
    if [ ! -f "$dir/scene.yaml" ]; then
      "$BIN/ausbau-scene-gen" --family "$family" --seed "$seed" --world random -o "$dir" --log-level warn ||
        { echo "planner-bench: ausbau-scene-gen failed for $family seed $seed" >&2; exit 2; }
    fi
    channels+=("$dir")
  done
done
list=$SCENES
for dir in "${channels[@]}"; do list="${list:+$list,}$(cd "$dir" && pwd)/scene.yaml"; done
[ -n "$list" ] || { echo "planner-bench: no scene (SCENES and CHANNEL_SEEDS are empty)" >&2; exit 2; }

args=(--planners ausbau-plan,cr-rrtc --ompl-ranges default --runs "$RUNS" --time-limit "$LIMIT"
      --scenes "$list" --output-dir "$OUT" --bin "$BIN")
[ -n "$RECORDED" ] && args+=(--recorded "$RECORDED")
"$BIN/ausbau-bench" "${args[@]}"
status=$?

# The channel paths as written (path.csv of each ausbau-plan run) through the oracle.
if [ ${#channels[@]} -gt 0 ]; then
  if ! /usr/bin/python3 -c 'import numpy' 2> /dev/null || [ ! -f "$ORACLE" ]; then
    echo "planner-bench: oracle not run (needs /usr/bin/python3 with numpy and $ORACLE)" | tee "$OUT/oracle.txt" >&2
  else
    valid=0 invalid=0 unsolved=0
    : > "$OUT/oracle.txt"
    for dir in "${channels[@]}"; do
      name=$(basename "$dir")
      for ((i = 0; i < RUNS; i++)); do
        csv="$OUT/ausbau-plan/$name-seed$((1 + i)).csv"
        if [ ! -s "$csv" ]; then unsolved=$((unsolved + 1)); echo "$name seed $((1 + i)): no path" >> "$OUT/oracle.txt"; continue; fi
        if /usr/bin/python3 "$ORACLE" "$dir" "$csv" > /dev/null 2>&1; then
          valid=$((valid + 1)); echo "$name seed $((1 + i)): oracle-valid" >> "$OUT/oracle.txt"
        else
          invalid=$((invalid + 1)); echo "$name seed $((1 + i)): ORACLE-INVALID" >> "$OUT/oracle.txt"
        fi
      done
    done
    line="planner-bench: channel families (ausbau-plan paths as written): $valid oracle-valid, $invalid invalid, $unsolved without a path"
    echo "$line" | tee -a "$OUT/oracle.txt"
    printf '\n## Channel families through oracle.py\n\n%s\n' "${line#planner-bench: }" >> "$OUT/summary.md"
    [ "$invalid" -eq 0 ] || status=1
  fi
fi
exit $status
