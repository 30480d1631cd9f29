#!/usr/bin/env bash
# The end-to-end benchmark of issue 14: the InIState pipeline
# (pipelines/inistate.mk) on every scene family, old and new, and on the
# external set, each path judged by a checker that is not the pipeline's:
#   - panel-* families and ../shared/benchmarks/inistate-external: the
#     external set's exact oracle.py on path.csv (reads boxes.json);
#   - clips-ds1 .. clips-ds5: ausbau-check-path against the generator's
#     ground truth (rigid parts' volume, disassembly).
# Per scene: correct (removable and the checker accepts the path), WRONG
# (removable but the checker rejects it: the worst result), not removable;
# and the wall time of the whole pipeline. A table per family at the end.
#
#   scripts/bench-exact.sh [OUT] [VALIDITY] [SEEDS]
#     OUT       folder for runs and results (default out/bench-exact)
#     VALIDITY  pipeline VALIDITY (default: the pipeline's default)
#     SEEDS     scene seeds, e.g. "1 2 3" (default "1 2 3")
# Needs a built build/bin and python3 with numpy (for oracle.py).
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/bench-exact}
validity=${2:-}
seeds=${3:-1 2 3}
bin=${BIN:-build/bin}
python=${PYTHON:-/usr/bin/python3}
external=${EXTERNAL:-../shared/benchmarks/inistate-external}
oracle=$external/oracle.py
mkdir -p "$out/scenes" "$out/runs"
results=$out/results.csv
echo "family,scene,verdict,checker,result,seconds" > "$results"
"$python" -c 'import numpy' 2>/dev/null || { echo "bench-exact: $python needs numpy (apt-get install python3-numpy)" >&2; exit 2; }

# run FAMILY NAME SCENE_DIR CHECKER(oracle|truth)
run() {
  local family=$1 name=$2 dir=$3 checker=$4 run=$out/runs/$2
  rm -rf "$run"
  local t0 t1 verdict result
  t0=$(date +%s.%N)
  make --no-print-directory -f pipelines/inistate.mk BIN="$bin" SCENE="$dir/scene.yaml" OUT="$run" WITH_REPORT=0 \
    ${validity:+VALIDITY=$validity} > "$run.log" 2>&1
  t1=$(date +%s.%N)
  verdict=not-removable
  grep -Eq '"removable"[[:space:]]*:[[:space:]]*true' "$run/verdict.json" 2>/dev/null && verdict=removable
  result=not-removable
  if [ "$verdict" = removable ]; then
    if [ "$checker" = oracle ]; then
      "$python" "$oracle" "$dir" "$run/path.csv" > "$run/oracle.json" 2>&1 && result=correct || result=WRONG
    else
      "$bin/ausbau-check-path" --scene "$dir/scene.yaml" --ground-truth "$dir/ground_truth.yaml" \
        --path "$run/path-smooth.h5" > "$run/check.txt" 2>&1 && result=correct || result=WRONG
    fi
  fi
  local seconds
  seconds=$(echo "$t1 - $t0" | bc)
  printf '%s,%s,%s,%s,%s,%.1f\n' "$family" "$name" "$verdict" "$checker" "$result" "$seconds" >> "$results"
  printf 'bench-exact: %-40s %-14s %-14s %6.1f s\n' "$name" "$verdict" "$result" "$seconds"
}

for family in clips-ds1 clips-ds2 clips-ds3 clips-ds4 clips-ds5; do
  for seed in $seeds; do
    dir=$out/scenes/$family-$seed
    [ -f "$dir/scene.yaml" ] || "$bin/ausbau-scene-gen" --family "$family" --seed "$seed" --triangles 2000 -o "$dir" > /dev/null
    run "$family" "$family-$seed" "$dir" truth
  done
done
for family in panel-tilt-slide panel-straight-pull panel-channel; do
  for seed in $seeds; do
    for tess in coarse fine; do
      dir=$out/scenes/$family-$tess-$seed
      [ -f "$dir/scene.yaml" ] || "$bin/ausbau-scene-gen" --family "$family" --seed "$seed" --tessellation "$tess" \
        --world random -o "$dir" > /dev/null
      run "$family-$tess" "$family-$tess-$seed" "$dir" oracle
    done
  done
done
for dir in "$external"/scenes/*/; do
  name=$(basename "$dir")
  run external "external-$name" "${dir%/}" oracle
done

# The table: per family, correct / WRONG / not removable, median and max time.
"$python" - "$results" <<'EOF' | tee "$out/summary.md"
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
families = []
for r in rows:
    if r["family"] not in families:
        families.append(r["family"])
print("| family | scenes | correct | wrongly removable | not removable | median s | max s |")
print("|---|---|---|---|---|---|---|")
for f in families + ["all"]:
    rs = [r for r in rows if f == "all" or r["family"] == f]
    t = [float(r["seconds"]) for r in rs]
    count = lambda v: sum(r["result"] == v for r in rs)
    print(f"| {f} | {len(rs)} | {count('correct')} | {count('WRONG')} | {count('not-removable')} | "
          f"{statistics.median(t):.1f} | {max(t):.1f} |")
EOF
