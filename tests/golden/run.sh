#!/usr/bin/env bash
# Golden outputs: the same seed gives byte-identical paths and verdicts.
#
#   tests/golden/run.sh BIN_DIR WORK_DIR [record]
#
# Runs the pipelines on six fixed cases (the demo scene, two clips-ds*
# scenes, three OMPL.app scenes) and compares path.csv, path-smooth.csv and
# the verdict (wall times and the output folder's name removed) with the
# files recorded in tests/golden/expected/, and checks that each run wrote
# only the files the manifest pipelines/run-files.txt declares. With `record`, writes them
# instead: do that only for a change that is meant to change the answers,
# and say why in the commit. The OMPL cases are skipped where
# ../shared/benchmarks/ompl/ is not there.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bin=$(cd "$1" && pwd)
work=$2
mode=${3:-check}
expected=$here/expected
ompl=$root/../shared/benchmarks/ompl
mkdir -p "$work"
work=$(cd "$work" && pwd)
failed=0

# The run's files and stages, named by the manifest pipelines/run-files.txt:
# run_file KEY prints the file name; STAGES is "plan|smooth|..." (every
# stage that writes a file: the verdict's stage_seconds keys).
manifest=$root/pipelines/run-files.txt
run_file() {
  local name
  name=$(awk -v key="$1" '$1 == key { print $2 }' "$manifest")
  [ -n "$name" ] || { echo "golden: $manifest declares no file '$1'" >&2; exit 2; }
  echo "$name"
}
STAGES=$(awk '!/^[[:space:]]*(#|$)/ && !seen[$4]++ { printf "%s%s", sep, $4; sep = "|" }' "$manifest")
PATH_CSV=$(run_file path-csv)
PATH_SMOOTH_CSV=$(run_file path-smooth-csv)
VERDICT_JSON=$(run_file verdict)

# The verdict without what changes from run to run: wall times, and the
# output folder's absolute name.
normalize_verdict() {
  grep -v -E "\"(seconds|total_seconds|$STAGES)\": [0-9.e+-]+,?\$" "$1" \
    | sed -e "s#$2/##g" -e "s#$work/##g" -e "s#$root/##g"
}

compare() {  # case file-in-work file-name-in-expected
  local name=$1 produced=$2 recorded=$expected/$1/$3
  if [ "$mode" = record ]; then
    mkdir -p "$expected/$name"; cp "$produced" "$recorded"; return
  fi
  if [ ! -f "$recorded" ]; then echo "golden $name: nothing recorded at $recorded"; failed=1; return; fi
  if ! cmp -s "$produced" "$recorded"; then
    echo "golden $name: $3 differs from the recorded one:"; diff "$recorded" "$produced" | head -20 || true; failed=1
  fi
}

# A run writes no file into OUT that the manifest does not declare (besides
# times/ and the hidden lock and caches): the manifest is the whole list.
check_declared() {  # case OUT
  local entry
  for entry in "$2"/*; do
    entry=$(basename "$entry")
    [ "$entry" = times ] && [ -d "$2/$entry" ] && continue
    awk -v file="$entry" '!/^[[:space:]]*(#|$)/ && $2 == file { found = 1 } END { exit !found }' "$manifest" ||
      { echo "golden $1: the run wrote $2/$entry, which $manifest does not declare"; failed=1; }
  done
}

inistate_case() {  # name scene.yaml
  local name=$1 scene=$2 out=$work/$1
  rm -rf "$out"
  # Smoothing's time limit must not decide a golden here either: under a
  # loaded make test, clips-ds2's sigma_1 shortcuts once stopped at half of
  # the 60 s limit (165 attempts instead of 225) and gave another path.
  make --no-print-directory -s -f "$root/pipelines/inistate.mk" SCENE="$scene" OUT="$out" BIN="$bin" SEED=1 \
    THREADS=${GOLDEN_THREADS:-2} WITH_REPORT=0 SMOOTH_FLAGS="--time-limit 604800" > "$work/$name.log" 2>&1 || true
  [ -f "$out/$VERDICT_JSON" ] || { echo "golden $name: no verdict ($work/$name.log)"; failed=1; return; }
  check_declared "$name" "$out"
  normalize_verdict "$out/$VERDICT_JSON" "$out" > "$out/verdict.normalized.json"
  compare "$name" "$out/verdict.normalized.json" "$VERDICT_JSON"
  if [ -f "$out/$PATH_CSV" ]; then compare "$name" "$out/$PATH_CSV" "$PATH_CSV"; fi
}

rigid_case() {  # name scene.yaml
  local name=$1 scene=$2 out=$work/$1
  rm -rf "$out"
  # Smoothing's time limit is a safety valve that must never decide a golden
  # (Apartment smooths in about 40 s on an idle core, more on a loaded CI):
  # a week here, so that only the seed decides.
  make --no-print-directory -s -f "$root/pipelines/plan.mk" SCENE="$scene" OUT="$out" BIN="$bin" SEED=1 \
    SMOOTH_FLAGS="--time-limit 604800" smooth > "$work/$name.log" 2>&1 || { echo "golden $name: the pipeline failed ($work/$name.log)"; failed=1; return; }
  check_declared "$name" "$out"
  compare "$name" "$out/$PATH_CSV" "$PATH_CSV"
  compare "$name" "$out/$PATH_SMOOTH_CSV" "$PATH_SMOOTH_CSV"
}

inistate_case demo "$root/scenes/panel-tilt-slide-1/scene.yaml"
inistate_case clips-ds1 "$root/scenes/clips-ds1/scene.yaml"
"$bin/ausbau-scene-gen" --family clips-ds2 --seed 2 --force -o "$work/clips-ds2-scene" > /dev/null 2>&1
inistate_case clips-ds2 "$work/clips-ds2-scene/scene.yaml"
for scene in Easy alpha-1.5 Apartment; do
  if [ -f "$ompl/$scene.yaml" ]; then rigid_case "ompl-$scene" "$ompl/$scene.yaml"
  else echo "golden ompl-$scene: skipped ($ompl/$scene.yaml not there)"; fi
done
if [ "$failed" != 0 ]; then echo "golden: FAILED (outputs in $work)"; exit 1; fi
echo "golden: all cases match ($mode)"
