#!/usr/bin/env bash
# The external benchmark set (../shared/benchmarks/inistate-external): every
# scene of scenes/ (box soup) and scenes-molded/ (the same scenes with D one
# welded solid) through the InIState pipeline (pipelines/inistate.mk, what
# `make run` runs), one after the other, each timed; its path.csv judged by
# the set's own oracle.py (exit 0: valid). Nothing here knows the answers:
# every scene of the set comes out (README of the set), so a NOT REMOVABLE
# verdict is a wrong answer and a removable verdict whose path the oracle
# refuses is WRONGLY REMOVABLE.
#
#   scripts/external-bench.sh [BIN] [OUT] [SET...]
#     BIN  folder of the stage executables (default build/bin)
#     OUT  output folder (default out/bench-external): OUT/<set>/<scene>/
#     SET  sub-folders of the set to run (default: scenes scenes-molded)
#   EXTERNAL (the set's folder), TIME_LIMIT (default 60), SEED (default 1)
#   and PYTHON (default /usr/bin/python3, needs numpy) from the environment.
#
# Prints a markdown table (set, scene, verdict, oracle, seconds) and the
# counts; exits 1 when any scene is wrongly removable, 0 otherwise.
set -u
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$HERE/build/bin}
OUT=${2:-out/bench-external}
shift $(($# < 2 ? $# : 2))
SETS=("$@"); [ ${#SETS[@]} -eq 0 ] && SETS=(scenes scenes-molded)
EXTERNAL=${EXTERNAL:-$HERE/../shared/benchmarks/inistate-external}
PYTHON=${PYTHON:-/usr/bin/python3}
BIN=$(cd "$BIN" && pwd) || { echo "external-bench: no folder $BIN" >&2; exit 2; }
[ -f "$EXTERNAL/oracle.py" ] || { echo "external-bench: no oracle.py in $EXTERNAL (set EXTERNAL)" >&2; exit 2; }
"$PYTHON" -c 'import numpy' 2>/dev/null || { echo "external-bench: $PYTHON has no numpy" >&2; exit 2; }
mkdir -p "$OUT" || exit 2
OUT=$(cd "$OUT" && pwd)

right=0 wrong=0 wrongly_removable=0
table="| set | scene | verdict | oracle | s |
|---|---|---|---|---:|"
for set in "${SETS[@]}"; do
  for dir in "$EXTERNAL/$set"/*/; do
    [ -f "$dir/scene.yaml" ] || continue
    name=$(basename "$dir")
    out="$OUT/$set/$name"
    rm -rf "$out" && mkdir -p "$out"
    start=$(date +%s.%N)
    make -s -C "$HERE" -f pipelines/inistate.mk SCENE="$dir/scene.yaml" OUT="$out" BIN="$BIN" \
      SEED="${SEED:-1}" TIME_LIMIT="${TIME_LIMIT:-60}" WITH_REPORT=0 > "$out/pipeline.log" 2>&1
    seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
    case $(sed -n 's/^ *"removable": *\([a-z]*\).*/\1/p' "$out/verdict.json" 2>/dev/null | head -n 1) in
      true) verdict=removable ;;
      false) verdict="NOT REMOVABLE" ;;
      *) verdict="(no verdict)" ;;
    esac
    oracle="-"
    if [ "$verdict" = removable ]; then
      if "$PYTHON" "$EXTERNAL/oracle.py" "$dir" "$out/path.csv" > "$out/oracle.log" 2>&1; then
        oracle=valid right=$((right + 1))
      else
        oracle=INVALID wrongly_removable=$((wrongly_removable + 1))
      fi
    else
      wrong=$((wrong + 1))
    fi
    table+=$'\n'"| $set | $name | $verdict | $oracle | $(printf '%.1f' "$seconds") |"
    echo "external-bench: $set/$name: $verdict, oracle $oracle, $(printf '%.1f' "$seconds") s" >&2
  done
done
summary="right $right, wrongly not removable $wrong, WRONGLY REMOVABLE $wrongly_removable"
printf '%s\n\n%s\n' "$table" "$summary" | tee "$OUT/external-bench.md"
[ "$wrongly_removable" -eq 0 ]
