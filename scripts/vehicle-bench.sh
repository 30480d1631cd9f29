#!/bin/bash
# The vehicle benchmark (issue 18, item 4): a generated body shell of about
# 1.2M triangles with PARTS fastened brackets (ausbau-scene-gen --family
# vehicle; every fifth riveted, i.e. blocked), then every part's InIState
# pipeline (pipelines/inistate.mk, VALIDITY=auto) with a time budget, one part
# after the other. S is cropped to each part's reach (docs/scenes.md: "Cropping S to
# D's reach").
#
#   scripts/vehicle-bench.sh BIN OUT [PARTS] [RUN] [BUDGET] [TIME_LIMIT] [MAX_CROP_LEVEL]
#     BIN             folder of the stage executables (build/bin)
#     OUT             output folder (the vehicle, one run folder per part, the table)
#     PARTS           parts generated (default 50)
#     RUN             how many of them are run (default: all; parts 00, 01, ...)
#     BUDGET          seconds per part, recorded by the verdict (default 120)
#     TIME_LIMIT      ausbau-plan --time-limit, shared by the crop levels (default 20)
#     MAX_CROP_LEVEL  ausbau-plan --max-crop-level (default 2)
#
# RUNNER=snakemake (environment; default make): the same parts through
# pipelines/Snakefile on CORES cores (default 2), one job per stage and
# part, THREADS=1 each, every part sharing one cache of S (the mesh cache and
# the distance fields in OUT/snakemake/.ausbau-cache). Per part it reports the
# sum of its stages' wall times (OUT/snakemake/<part>/times); the totals are
# the whole run's wall and CPU time and peak memory (/usr/bin/time -v on
# snakemake: the largest resident set of any one process).
#
# Writes OUT/vehicle-bench.md: the machine, then per part: expected answer
# (clipped: removable, riveted: blocked), the verdict, wall time, peak
# memory (the largest resident set of any stage, /usr/bin/time -v on make),
# within budget; then the totals. Exits 1 when a verdict differs from the
# expected one (a removable riveted part would be a wrong "removable").
set -u
if [ $# -lt 2 ]; then
  sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
BIN=$(cd "$1" && pwd) || exit 2
OUT=$2
PARTS=${3:-50}
RUN=${4:-$PARTS}
BUDGET=${5:-120}
TIME_LIMIT=${6:-20}
MAX_CROP_LEVEL=${7:-2}
HERE=$(cd "$(dirname "$0")/.." && pwd)
TIME=/usr/bin/time
[ -x "$TIME" ] || { echo "vehicle-bench: needs GNU time (/usr/bin/time; apt-get install time)" >&2; exit 2; }
mkdir -p "$OUT" || exit 2
OUT=$(cd "$OUT" && pwd)

gen_start=$(date +%s.%N)
"$TIME" -v -o "$OUT/generate.time" "$BIN/ausbau-scene-gen" --family vehicle --parts "$PARTS" --force -o "$OUT/vehicle" \
  > "$OUT/parts.txt" || exit 1
gen_s=$(awk -v a="$gen_start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
shell_triangles=$(grep -c '^f ' "$OUT/vehicle/shell.obj")

# Every part's stages share one mesh cache (pipelines/batch.mk does the same
# for an assembly): the shell is parsed by the first part's first stage and
# read from the cache by every other. Emptied first, so that the total
# includes that one parse.
rm -rf "$OUT/cache"
export AUSBAU_CACHE_DIR="$OUT/cache" AUSBAU_MESH_CACHE="$OUT/cache"

rows=""
removable=0 blocked=0 wrong=0 over=0 n=0 total_s=0 max_kb=0
machine_line() {
  echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(awk '/MemTotal/ { printf "%.0f GB", $2 / 1048576 }' /proc/meminfo); load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
}
# One row per part: the verdict in RUN_DIR/verdict.json against the expected one.
judge_part() {  # part kind run_dir seconds cpu kb
  local part=$1 kind=$2 run=$3 seconds=$4 cpu=$5 kb=$6 verdict expected within
  if grep -Eq '"removable"[[:space:]]*:[[:space:]]*true' "$run/verdict.json" 2>/dev/null; then
    verdict=removable; removable=$((removable + 1))
  elif [ -f "$run/verdict.json" ]; then
    verdict=blocked; blocked=$((blocked + 1))
  else
    verdict="error (see $part.log)"
  fi
  expected=removable; [ "$kind" = riveted ] && expected=blocked
  [ "$verdict" = "$expected" ] || wrong=$((wrong + 1))
  within=yes
  awk -v s="$seconds" -v b="$BUDGET" 'BEGIN { exit !(s > b) }' && { within=no; over=$((over + 1)); }
  rows+="| $part | $kind | $expected | $verdict | $seconds | $cpu | $kb | $within |"$'\n'
  echo "vehicle-bench: $part ($kind): $verdict, $seconds s" >&2
}

if [ "${RUNNER:-make}" = snakemake ]; then
  command -v snakemake > /dev/null || { echo "vehicle-bench: RUNNER=snakemake: snakemake is not installed (scripts/install-deps.sh snakemake)" >&2; exit 2; }
  CORES=${CORES:-2}
  list=()
  while read -r scene kind; do
    [ "${#list[@]}" -ge "$RUN" ] && break
    list+=("$scene")
  done < "$OUT/parts.txt"
  n=${#list[@]}
  rm -rf "$OUT/snakemake"
  mkdir -p "$OUT/snakemake"
  unset AUSBAU_CACHE_DIR AUSBAU_MESH_CACHE  # the Snakefile's own: OUT/snakemake/.ausbau-cache
  start=$(date +%s.%N)
  "$TIME" -v -o "$OUT/snakemake.time" snakemake -s "$HERE/pipelines/Snakefile" --directory "$OUT/snakemake" \
    --cores "$CORES" --keep-going --config SCENE_LIST="${list[*]}" OUT="$OUT/snakemake" BIN="$BIN" THREADS=1 \
    WITH_REPORT=0 BUDGET="$BUDGET" TIME_LIMIT="$TIME_LIMIT" PLAN_FLAGS="--max-crop-level $MAX_CROP_LEVEL" \
    > "$OUT/snakemake.log" 2>&1
  total_s=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  max_kb=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$OUT/snakemake.time")
  total_cpu=$(awk -F': ' '/User time/ { u = $2 } /System time/ { s = $2 } END { printf "%.1f", u + s }' "$OUT/snakemake.time")
  i=0
  while read -r scene kind; do
    [ "$i" -ge "$n" ] && break
    i=$((i + 1))
    part=$(basename "$(dirname "$scene")")
    seconds=$(cat "$OUT/snakemake/$part"/times/*.seconds 2>/dev/null | awk '{ s += $1 } END { printf "%.1f", s }')
    judge_part "$part" "$kind" "$OUT/snakemake/$part" "$seconds" "-" "-"
  done < "$OUT/parts.txt"
  {
    machine_line
    echo
    echo "Vehicle: shell $shell_triangles triangles, $PARTS parts (every fifth riveted), generated in $gen_s s; $n parts run through pipelines/Snakefile on $CORES cores (THREADS=1); budget $BUDGET s per part, --time-limit $TIME_LIMIT, --max-crop-level $MAX_CROP_LEVEL"
    echo
    echo "| part | kind | expected | verdict | stage wall s | CPU s | peak MiB | within budget |"
    echo "|---|---|---|---|---:|---:|---:|---|"
    printf '%s' "$rows"
    echo
    echo "Totals: $removable removable, $blocked blocked, $wrong not as expected, $over over budget; $total_s s wall and $total_cpu s CPU for $n parts (snakemake and every job); peak memory $((max_kb / 1024)) MiB (one process); projection for 800 parts: $(awk -v t="$total_s" -v n="$n" 'BEGIN { printf "%.0f min", t / n * 800 / 60 }')."
  } > "$OUT/vehicle-bench.md"
  cat "$OUT/vehicle-bench.md"
  [ "$wrong" -eq 0 ]
  exit
fi

while read -r scene kind; do
  [ "$n" -ge "$RUN" ] && break
  n=$((n + 1))
  part=$(basename "$(dirname "$scene")")
  run="$OUT/runs/$part"
  rm -rf "$run"
  start=$(date +%s.%N)
  "$TIME" -v -o "$OUT/$part.time" make -s -f "$HERE/pipelines/inistate.mk" SCENE="$scene" OUT="$run" BIN="$BIN" \
    WITH_REPORT=0 BUDGET="$BUDGET" TIME_LIMIT="$TIME_LIMIT" PLAN_FLAGS="--max-crop-level $MAX_CROP_LEVEL" \
    > "$OUT/$part.log" 2>&1
  seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  kb=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$OUT/$part.time")
  cpu=$(awk -F': ' '/User time/ { u = $2 } /System time/ { s = $2 } END { printf "%.1f", u + s }' "$OUT/$part.time")
  judge_part "$part" "$kind" "$run" "$seconds" "$cpu" "$((kb / 1024))"
  total_s=$(awk -v a="$total_s" -v b="$seconds" 'BEGIN { printf "%.1f", a + b }')
  [ "$kb" -gt "$max_kb" ] && max_kb=$kb
done < "$OUT/parts.txt"

{
  machine_line
  echo
  echo "Vehicle: shell $shell_triangles triangles, $PARTS parts (every fifth riveted), generated in $gen_s s; $n parts run; budget $BUDGET s per part, --time-limit $TIME_LIMIT, --max-crop-level $MAX_CROP_LEVEL"
  echo
  echo "| part | kind | expected | verdict | wall s | CPU s | peak MiB | within budget |"
  echo "|---|---|---|---|---:|---:|---:|---|"
  printf '%s' "$rows"
  echo
  echo "Totals: $removable removable, $blocked blocked, $wrong not as expected, $over over budget; $total_s s wall for $n parts; peak memory $((max_kb / 1024)) MiB; projection for 800 parts: $(awk -v t="$total_s" -v n="$n" 'BEGIN { printf "%.0f min", t / n * 800 / 60 }')."
} > "$OUT/vehicle-bench.md"
cat "$OUT/vehicle-bench.md"
[ "$wrong" -eq 0 ]
