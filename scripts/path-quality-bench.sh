#!/usr/bin/env bash
# Path quality on generated scenes with a known path: each family x seed is
# generated (coarse boxes, a random world placement), run through the
# InIState pipeline (pipelines/inistate.mk, defaults), and its path.csv
# measured against the known path by ausbau-path-quality (translation at D's
# reference point within 1.25x the known path's extended to the same goal,
# rotation within the known path's + 0.1 rad).
#   scripts/path-quality-bench.sh BIN OUT [SEEDS] [FAMILIES]
# Writes OUT/results.csv (one row per scene) and OUT/summary.md; prints the
# summary. Exit 0 whatever the figures (a benchmark, not a test).
set -euo pipefail
bin=${1:?usage: path-quality-bench.sh BIN OUT [SEEDS] [FAMILIES]}
out=${2:?usage: path-quality-bench.sh BIN OUT [SEEDS] [FAMILIES]}
seeds=${3:-1 2 3 4}
families=${4:-panel-tilt-slide panel-straight-pull panel-channel clips-ds1 clips-ds2 clips-ds3 clips-ds4 clips-ds5}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
results="$out/results.csv"
echo "family,seed,pipeline_exit,scene,translation,rotation,straight,ratio,known_translation,known_rotation,translation_ok,rotation_ok,seconds" > "$results"
for family in $families; do
  for seed in $seeds; do
    dir="$out/$family-$seed"
    rm -rf "$dir"
    "$bin/ausbau-scene-gen" --family "$family" --seed "$seed" -o "$dir/scene" > /dev/null 2>&1
    known="$dir/scene/truth/known_path.csv"
    [ -f "$known" ] || known="$dir/scene/ground_truth_path.csv"
    start=$(date +%s.%N)
    set +e
    make -s -C "$here" -f pipelines/inistate.mk SCENE="$dir/scene/scene.yaml" OUT="$dir/run" BIN="$bin" \
      WITH_REPORT=0 > "$dir/pipeline.log" 2>&1
    code=$?
    set -e
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    row=",,,,,,,0,0"
    if [ -f "$dir/run/path.csv" ]; then
      row=$("$bin/ausbau-path-quality" --scene "$dir/scene/scene.yaml" --path-csv "$dir/run/path.csv" --known "$known" \
        2> "$dir/quality.err" || echo ",,,,,,,0,0")
      row=${row#*,}
    fi
    echo "$family,$seed,$code,$family-$seed,$row,$seconds" >> "$results"
    echo "$family seed $seed: exit $code, $row" >&2
  done
done
{
  echo "# Path quality against the known paths"
  echo
  echo "$(uname -srm), $(nproc) cores; $(date -u +%Y-%m-%d); seeds: $seeds"
  echo
  echo "| family | scenes | solved | translation ok | rotation ok | both ok | median ratio ours/known translation | median rotation (rad) ours / known |"
  echo "|---|---|---|---|---|---|---|---|"
  awk -F, 'NR > 1 { n[$1]++; if ($3 == 0) s[$1]++; if ($11 == 1) t[$1]++; if ($12 == 1) r[$1]++; if ($11 == 1 && $12 == 1) b[$1]++;
                    if ($9 > 0) q[$1] = q[$1] " " $5 / $9; rr[$1] = rr[$1] " " $6 "/" $10 }
       function median(list,   a, k, i, j, tmp) { k = split(list, a, " "); for (i = 1; i <= k; i++) for (j = i + 1; j <= k; j++) if (a[j] + 0 < a[i] + 0) { tmp = a[i]; a[i] = a[j]; a[j] = tmp }
                                               return k ? a[int((k + 1) / 2)] : "-" }
       END { for (f in n) { all += n[f]; both += b[f];
               printf "| %s | %d | %d | %d | %d | %d | %.2f | %s |\n", f, n[f], s[f], t[f], r[f], b[f], median(q[f]), rr[f] }
             printf "\n**%d of %d scenes (%.0f%%) within both bounds.**\n", both, all, all ? 100 * both / all : 0 }' "$results"
} > "$out/summary.md"
cat "$out/summary.md"
