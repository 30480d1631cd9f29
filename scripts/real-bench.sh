#!/bin/bash
# The real-mesh benchmark (make bench-real): every bench/real/*/scene.yaml
# through the InIState pipeline (pipelines/inistate.mk, what `make run` runs,
# without rebuilding per scene), one scene after the other, each timed; its
# verdict.json compared with the scene's expected.yaml.
#
#   scripts/real-bench.sh [BIN] [OUT] [SCENES]
#     BIN     folder of the stage executables (default build/bin)
#     OUT     output folder (default out/bench-real): OUT/<scene>/ per scene,
#             OUT/real-bench.md the table
#     SCENES  folder of the scene folders (default bench/real)
#   TIME_LIMIT, SEED, VALIDITY, BUDGET from the environment are passed to the
#   pipeline when set.
#
# Prints a markdown table: scene, expected, verdict, right / wrong /
# WRONGLY-REMOVABLE, the exact check's deepest rigid penetration, seconds;
# then the counts and the median time. A scene whose expected.yaml has
# `removable: false` and `accept_removable: true` (a nut on a bolt: a helical
# unscrewing is a rigid motion too) counts as right either way, provided a
# removable verdict's exact check passed with no fastener deeper than the
# tolerance either (the tool may take the nut's thread for snap fasteners that
# give way: a straight pull through the thread is no unscrewing), with no fit
# interference allowed along it (an overlap passed as a fit lets a straight
# pull through the thread within its installed depth: no unscrewing either),
# and turning D by more than a radian (an unscrewing turns).
# Exits 1 when any scene is wrongly removable, 0 otherwise (wrong NOT
# REMOVABLE answers are reported, not failed: see bench/real/README.md).
set -u
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$HERE/build/bin}
OUT=${2:-out/bench-real}
SCENES=${3:-$HERE/bench/real}
BIN=$(cd "$BIN" && pwd) || { echo "real-bench: no folder $BIN" >&2; exit 2; }
mkdir -p "$OUT" || exit 2
OUT=$(cd "$OUT" && pwd)
vars=()
for v in TIME_LIMIT SEED VALIDITY BUDGET; do
  if [ -n "${!v:-}" ]; then vars+=("$v=${!v}"); fi
done

# yaml_value KEY FILE: a top-level `key: value` of expected.yaml (comment and quotes removed)
yaml_value() {
  sed -n "s/^$1:[[:space:]]*\([^#]*\).*$/\1/p" "$2" | head -n 1 | sed 's/[[:space:]]*$//; s/^"\(.*\)"$/\1/'
}
# json_value KEY FILE: the first `"KEY": value` of verdict.json (one key per line)
json_value() {
  sed -n "s/^[[:space:]]*\"$1\":[[:space:]]*\"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}[[:space:]]*$/\1/p" "$2" | head -n 1
}

table="$OUT/real-bench.md"
{
  echo "| scene | expected | verdict | result | exact-check rigid depth | seconds |"
  echo "|---|---|---|---|---|---|"
} > "$table"
cat "$table"
right=0 wrong=0 wrongly=0 failed=0 n=0
times=()
for scene_yaml in "$SCENES"/*/scene.yaml; do
  [ -f "$scene_yaml" ] || continue
  dir=$(dirname "$scene_yaml")
  name=$(basename "$dir")
  expected_yaml="$dir/expected.yaml"
  expected=$(yaml_value removable "$expected_yaml" 2>/dev/null)
  accept=$(yaml_value accept_removable "$expected_yaml" 2>/dev/null)
  run="$OUT/$name"
  n=$((n + 1))
  start=$(date +%s.%N)
  make -s -f "$HERE/pipelines/inistate.mk" SCENE="$scene_yaml" OUT="$run" BIN="$BIN" "${vars[@]}" \
    > "$OUT/$name.log" 2>&1
  code=$?
  seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  times+=("$seconds")
  verdict_json="$run/verdict.json"
  depth=-
  if [ -f "$verdict_json" ]; then
    removable=$(json_value removable "$verdict_json")
    valid=$(json_value valid "$verdict_json")
    depth=$(json_value max_rigid_penetration "$verdict_json")
    fdepth=$(json_value max_fastener_penetration "$verdict_json")
    tol=$(json_value rigid_tolerance "$verdict_json")
    rigid_only=$(awk -v f="${fdepth:-x}" -v t="${tol:-x}" 'BEGIN { print (f ~ /^[0-9.eE+-]+$/ && t ~ /^[0-9.eE+-]+$/ && f + 0 <= t + 0) ? "yes" : "no" }')
    # The first "rotation" is the path's total turn (verdict.json "length").
    turn=$(json_value rotation "$verdict_json")
    tr -d ' \n' < "$verdict_json" | grep -q '"fit_interferences":\[\]' || rigid_only=no
    awk -v r="${turn:-x}" 'BEGIN { exit !(r ~ /^[0-9.eE+-]+$/ && r + 0 > 1) }' || rigid_only=no
    case $removable in
      true) verdict=REMOVABLE ;;
      false) verdict="NOT REMOVABLE" ;;
      *) verdict="failed($code)" ;;
    esac
  else
    removable=? valid=? rigid_only=no verdict="failed($code)"
  fi
  case $verdict in
    failed*) result=failed; failed=$((failed + 1)) ;;
    *)
      if [ "$removable" = "$expected" ]; then result=right; right=$((right + 1))
      elif [ "$removable" = true ] && [ "$accept" = true ] && [ "$valid" = true ] && [ "$rigid_only" = yes ]; then
        result="right (accepted removable)"; right=$((right + 1))
      elif [ "$removable" = true ]; then result=WRONGLY-REMOVABLE; wrongly=$((wrongly + 1))
      else result=wrong; wrong=$((wrong + 1)); fi ;;
  esac
  case $expected in true) exp=removable ;; false) exp="not removable" ;; *) exp="? ($expected)" ;; esac
  row="| $name | $exp | $verdict | $result | ${depth:--} | $seconds |"
  echo "$row" >> "$table"
  echo "$row"
done
median=$(printf '%s\n' "${times[@]}" | sort -n | awk '{ a[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print a[(NR + 1) / 2]; else printf "%.1f\n", (a[NR / 2] + a[NR / 2 + 1]) / 2 }')
summary="real-bench: $n scenes: $right right, $wrong wrong (not removable but removable), $wrongly WRONGLY-REMOVABLE, $failed failed; median $median s per scene (logs: $OUT/<scene>.log, table: $table)"
printf '\n%s\n' "$summary" >> "$table"
printf '\n%s\n' "$summary"
[ "$wrongly" -eq 0 ]
