#!/bin/bash
# What each piece of the rigid planner buys (issue 29 item 2): ausbau-plan as
# a user runs it, once with its defaults and once per variant that switches
# one piece off or swaps it, on the narrow-passage scenes, same seeds, one
# process per run, timed from spawn to exit.
#
#   scripts/planner-ablation.sh BIN OUT RUNS TIME_LIMIT [SCENES] [VARIANTS]
#     BIN         folder of ausbau-plan and ausbau-scene-gen
#     OUT         output folder: results.csv (one row per run), table.md,
#                 per run <variant>/<scene>-seed<N>.log
#     RUNS        seeds per cell (1..RUNS); TIME_LIMIT seconds per run
#     SCENES      space-separated: an OMPL.app scene name (in
#                 ../shared/benchmarks/ompl), a scene.yaml path, or
#                 panel-channel-sN, panel-zchannel-sN or panel-keyhole-sN
#                 (generated here, seed N, random world placement);
#                 default below
#     VARIANTS    space-separated names from the list below; default: all
#
# A failure counts as TIME_LIMIT seconds in the median time; the checks are
# the solved runs' (planning and certification). The variants:
#   default       cr-rrtc, uniform samples, FCL, certification (the
#                 collision validity plans without restarts: those are
#                 rigid-exact's, the pipeline's default)
#   def-rrtc      RRT-Connect with the thesis's fixed u and range (Def-RRTC)
#   no-passage    no second try of a trapped extension along the nearby
#                 nodes' principal directions (--passage-neighbors 0)
#   no-exits      no exit moves (pulls out, quarter turns) from new nodes
#                 of the start tree (--exit-axes 0; disassembly only)
#   exits-3       exit moves about all three of D's normal axes (--exit-axes 3)
#   single-pulls  single straight pulls only: no two legs, no sampling from
#                 where the pulls stopped (--pull-legs 1; disassembly only)
#   gaussian      Gaussian sampling near obstacles (Boor et al. 1999)
#   bridge        the bridge test (Hsu et al. 2003)
#   mixed         a third each of uniform, Gaussian and bridge samples
#   farr          FARR rays in front of FCL (the fields built in OUT/cache)
#   no-coarse     no coarse first search (--coarse-iterations 0): the
#                 search at 1% from the start
#   coarse-step   the search at 4% of D's diagonal only, no search at the
#                 thesis's 1% after it (certified at 0.25% either way)
#   fine-edges    planned at the certification's step (0.25%): what
#                 planning at 1% and certifying the path saves
# Exit 2 on bad usage; otherwise 0 (a table, not a check).
set -u
[ $# -ge 4 ] || { echo "usage: planner-ablation.sh BIN OUT RUNS TIME_LIMIT [SCENES] [VARIANTS]" >&2; exit 2; }
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=$(cd "$1" && pwd) || { echo "planner-ablation: no folder $1" >&2; exit 2; }
OUT=$2
RUNS=$3
LIMIT=$4
SCENES=${5:-"alpha-1.5 alpha-1.2 Twistycool Home bugtrap panel-channel-s1"}
VARIANTS=${6:-"default no-coarse coarse-step def-rrtc no-passage gaussian bridge mixed farr fine-edges"}
case "$RUNS" in '' | *[!0-9]*) echo "planner-ablation: RUNS '$RUNS' is not a number" >&2; exit 2 ;; esac
case "$LIMIT" in '' | *[!0-9.]*) echo "planner-ablation: TIME_LIMIT '$LIMIT' is not a number" >&2; exit 2 ;; esac
OMPL_DIR=$HERE/../shared/benchmarks/ompl
mkdir -p "$OUT/scenes" "$OUT/cache" || exit 2
OUT=$(cd "$OUT" && pwd)
export AUSBAU_CACHE_DIR="$OUT/cache"

flags_of() {
  case "$1" in
    default) echo "" ;;
    def-rrtc) echo "--planner rrtc" ;;
    no-passage) echo "--passage-neighbors 0" ;;
    no-exits) echo "--exit-axes 0" ;;
    exits-3) echo "--exit-axes 3" ;;
    single-pulls) echo "--pull-legs 1" ;;
    gaussian) echo "--sampler gaussian" ;;
    bridge) echo "--sampler bridge" ;;
    mixed) echo "--sampler mixed" ;;
    farr) echo "--collision farr" ;;
    no-coarse) echo "--coarse-iterations 0" ;;
    coarse-step) echo "--resolution 0.04" ;;
    fine-edges) echo "--resolution 0.0025 --coarse-iterations 0" ;;
    *) return 1 ;;
  esac
}
for variant in $VARIANTS; do
  flags_of "$variant" > /dev/null || { echo "planner-ablation: unknown variant '$variant'" >&2; exit 2; }
done

scene_file() {  # the scene.yaml of a SCENES item
  case "$1" in
    panel-channel-s* | panel-zchannel-s* | panel-keyhole-s*)
      local family=${1%-s*} seed=${1##*-s} dir="$OUT/scenes/$1"
      case "$seed" in '' | *[!0-9]*) return 1 ;; esac
      [ -f "$dir/scene.yaml" ] ||
        "$BIN/ausbau-scene-gen" --family "$family" --seed "$seed" --world random -o "$dir" --log-level warn || return 1
      echo "$dir/scene.yaml" ;;
    */*) [ -f "$1" ] && echo "$1" ;;
    *) [ -f "$OMPL_DIR/$1.yaml" ] && echo "$OMPL_DIR/$1.yaml" ;;
  esac
}
for scene in $SCENES; do
  scene_file "$scene" > /dev/null || { echo "planner-ablation: no scene '$scene'" >&2; exit 2; }
done

results=$OUT/results.csv
echo "variant,scene,seed,exit,wall_s,iterations,checks" > "$results"
for scene in $SCENES; do
  file=$(scene_file "$scene")
  name=$(basename "$scene" .yaml)
  for variant in $VARIANTS; do
    read -r -a flags <<< "$(flags_of "$variant")"
    mkdir -p "$OUT/$variant"
    for seed in $(seq 1 "$RUNS"); do
      log="$OUT/$variant/$name-seed$seed.log"
      start=$(date +%s.%N)
      "$BIN/ausbau-plan" --scene "$file" -o "$OUT/$variant/$name-seed$seed.h5" --force --seed "$seed" \
        --time-limit "$LIMIT" "${flags[@]}" > "$log" 2>&1
      code=$?
      end=$(date +%s.%N)
      wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')
      # "planning solved after 1.775 s: 6996 iterations, 2105 nodes, 137279 validity checks"
      stats=$(sed -n 's/.*: \([0-9]*\) iterations, [0-9]* nodes, \([0-9]*\) validity checks.*/\1,\2/p' "$log" | tail -1)
      echo "$variant,$name,$seed,$code,$wall,${stats:-,}" >> "$results"
      echo "planner-ablation: $variant $name seed $seed: exit $code, $wall s" >&2
    done
  done
done

# The table: per scene and variant, the runs solved, the median wall time
# (a failure counted as the limit) and the median validity checks of the
# solved runs (work: the same on any machine, where the clock did not stop
# a run).
{
  echo "| variant | $(for s in $SCENES; do printf '%s | ' "$(basename "$s" .yaml)"; done)"
  echo "|---|$(for s in $SCENES; do printf -- '---:|'; done)"
  for variant in $VARIANTS; do
    row="| $variant |"
    for scene in $SCENES; do
      name=$(basename "$scene" .yaml)
      cell=$(awk -F, -v v="$variant" -v s="$name" -v limit="$LIMIT" '
        function median(a, k,   i, j, x) {
          for (i = 1; i <= k; i++) for (j = i + 1; j <= k; j++) if (a[j] < a[i]) { x = a[i]; a[i] = a[j]; a[j] = x }
          return (k % 2) ? a[(k + 1) / 2] : (a[k / 2] + a[k / 2 + 1]) / 2
        }
        $1 == v && $2 == s { n++; if ($4 == 0) { ok++; t[n] = $5; c[ok] = $7 } else t[n] = limit }
        END {
          if (n == 0) { print "-"; exit }
          printf "%d/%d, %.2f s", ok, n, median(t, n)
          if (ok > 0) printf ", %.0fk checks", median(c, ok) / 1000
        }' "$results")
      row="$row $cell |"
    done
    echo "$row"
  done
} > "$OUT/table.md"
cat "$OUT/table.md"
