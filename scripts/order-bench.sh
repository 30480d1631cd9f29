#!/usr/bin/env bash
# The disassembly order on real meshes (make bench-order): the assemblies of
# bench/real/tools/order_assemblies.py (parts of the bench/real scenes, in
# their assembled poses) through ausbau-order, each order compared with the
# one the geometry gives (steps; within a step the parts in any order).
#
#   scripts/order-bench.sh [BIN] [OUT]
#     BIN  folder of the stage executables (default build/bin)
#     OUT  output folder (default out/bench-order): OUT/<assembly>/parts,
#          expected.txt, order/ (ausbau-order's output), order.log
#   PART_BUDGET (default 10 s per attempt), SEED (default 1) and PYTHON
#   (default /usr/bin/python3, needs numpy) from the environment.
#
# Prints a markdown table (assembly, expected steps, found steps, right or
# WRONG, seconds); exits 1 when any order differs from the expected one.
set -u
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$HERE/build/bin}
OUT=${2:-out/bench-order}
PYTHON=${PYTHON:-/usr/bin/python3}
BIN=$(cd "$BIN" && pwd) || { echo "order-bench: no folder $BIN" >&2; exit 2; }
"$PYTHON" -c 'import numpy' 2>/dev/null || { echo "order-bench: $PYTHON has no numpy" >&2; exit 2; }
mkdir -p "$OUT" || exit 2
OUT=$(cd "$OUT" && pwd)
"$PYTHON" "$HERE/bench/real/tools/order_assemblies.py" "$OUT" > "$OUT/assemblies.txt" || exit 2

wrong=0
echo "| assembly | expected steps | found steps | result | s |"
echo "|---|---|---|---|---:|"
while read -r name; do
  dir="$OUT/$name"
  fixed=$(head -n 1 "$dir/expected.txt")
  expected=$(tail -n +2 "$dir/expected.txt" | paste -sd ';' | sed 's/;/; /g')
  rm -rf "$dir/order"
  start=$(date +%s.%N)
  "$BIN/ausbau-order" --parts-dir "$dir/parts" --fixed "$fixed" --part-budget "${PART_BUDGET:-10}" \
    --seed "${SEED:-1}" --output-dir "$dir/order" > "$dir/order.log" 2>&1
  seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  found=$("$PYTHON" - "$dir/order/order.json" <<'PY'
import json, sys
try:
    order = json.load(open(sys.argv[1]))
except (OSError, ValueError):
    print('(no order.json)'); sys.exit()
steps = [' '.join(sorted(step)) for step in order['steps']]
if not order.get('complete'):
    steps.append('left: ' + ' '.join(order.get('remaining', [])))
print('; '.join(steps))
PY
)
  if [ "$found" = "$expected" ]; then result=right; else result=WRONG; wrong=$((wrong + 1)); fi
  echo "| $name | $expected | $found | $result | $seconds |"
done < "$OUT/assemblies.txt"
[ "$wrong" -eq 0 ]
