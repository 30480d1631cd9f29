#!/usr/bin/env bash
# ausbau-report without a browser (CTest: report_self_contained):
#   tests/browser/check_report.sh BIN_DIR WORK_DIR HELPER
# - the HTML is one self-contained file: no script, link, img or iframe that
#   loads anything by URL (http://, https://, //host or a relative file),
#   three.js inlined (the import map's data: URLs), the viewer inlined;
# - bad input exits 2 with one line `ausbau-report: error: ...`: a missing
#   scene, a file that is not HDF5, an artifact of another schema (labels)
#   given as the path, a missing path file, no --scene, a missing run
#   folder, an unknown option;
# - --bench-dir turns ausbau-bench-like outputs into one page (tables,
#   inlined SVG, bar chart).
set -euo pipefail
usage="usage: check_report.sh BIN_DIR WORK_DIR HELPER"
bin=$(cd "${1:?$usage}" && pwd)
work=${2:?$usage}
helper=${3:?$usage}
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)
report=$bin/ausbau-report
failures=0
fail() { echo "check_report: FAIL: $*" >&2; failures=$((failures + 1)); }

"$bin/ausbau-scene-gen" --family two-boxes --seed 1 -o "$work/scene" >/dev/null
scene=$work/scene/scene.yaml
"$bin/ausbau-plan" --scene "$scene" --seed 1 --time-limit 30 -o "$work/path.h5" --log-level warn
"$report" --scene "$scene" --path "$work/path.h5" -o "$work/report.html" --log-level warn
html=$work/report.html

# Self-contained: nothing is loaded by URL.
if grep -Eio '<(script|link|img|iframe|source|video|audio|embed)[^>]*(src|href)=[^>]*>' "$html" | head -3 | grep .; then
  fail "the page loads something by URL (lines above)"
fi
if grep -Eo '(import|from)[[:space:]]*["'"'"'](https?:)?//[^"'"'"']*' "$html" | head -3 | grep .; then
  fail "the page imports a module by URL"
fi
grep -q '<script type="importmap">{"imports":{"three":"data:text/javascript;base64,' "$html" ||
  fail "three.js is not inlined through the import map"
grep -q 'three/addons/controls/OrbitControls.js":"data:text/javascript;base64,' "$html" ||
  fail "OrbitControls is not inlined"
grep -q 'window.ausbau' "$html" || fail "the viewer module is not inlined"
grep -q 'id="ausbau-buf-0"' "$html" || fail "no binary mesh buffers"
[ "$(grep -c '</html>' "$html")" -eq 1 ] || fail "not one HTML document"

# The answer first: a headline (no verdict.json here), before the 3D view.
grep -q '<section id="headline" class="headline none"><span id="verdict-word">NO VERDICT</span>' "$html" ||
  fail "no headline 'NO VERDICT' (no verdict.json given)"
[ "$(grep -bo 'id="headline"' "$html" | head -1 | cut -d: -f1)" -lt "$(grep -bo 'id="view"' "$html" | head -1 | cut -d: -f1)" ] ||
  fail "the headline does not come before the 3D view"
# The download: the path as CSV, one row per waypoint, in a data: URL.
csv_b64=$(grep -o 'id="download-planned" class="download" download="path.csv" href="data:text/csv;base64,[A-Za-z0-9+/=]*' "$html" |
  sed 's/.*base64,//')
[ -n "$csv_b64" ] || fail "no download link for the planned path"
waypoints=$(h5dump -d /waypoints -H "$work/path.h5" | grep -o 'DATASPACE  SIMPLE { ( [0-9]*' | grep -o '[0-9]*$')
rows=$(printf '%s' "$csv_b64" | base64 -d | tail -n +2 | wc -l)
[ "$(printf '%s' "$csv_b64" | base64 -d | head -1)" = "x,y,z,qw,qx,qy,qz" ] || fail "the downloaded CSV has another header"
[ "$rows" = "$waypoints" ] || fail "the downloaded CSV has $rows rows, the path $waypoints waypoints"

# Deterministic: the same inputs give the same bytes.
"$report" --scene "$scene" --path "$work/path.h5" -o "$work/report2.html" --log-level warn
cmp -s "$html" "$work/report2.html" || fail "two runs gave different HTML"

# Bad input: exit 2 and one line "ausbau-report: error: ...".
expect_error() {  # expect_error FRAGMENT ARGS...
  local fragment=$1 out code=0
  shift
  out=$("$report" "$@" -o "$work/bad.html" 2>&1) || code=$?
  if [ "$code" -ne 2 ]; then fail "ausbau-report $* exited $code (expected 2): $out"; return; fi
  if [ "$(printf '%s\n' "$out" | wc -l)" -ne 1 ]; then fail "ausbau-report $*: more than one line: $out"; return; fi
  case "$out" in
    "ausbau-report: error: "*"$fragment"*) ;;
    *) fail "ausbau-report $*: expected 'ausbau-report: error: ...$fragment...', got: $out" ;;
  esac
  [ ! -e "$work/bad.html" ] || fail "ausbau-report $* wrote an output"
}
expect_error "file not found" --scene "$work/nope.yaml" --path "$work/path.h5"
expect_error "not a readable HDF5 file" --scene "$scene" --path "$scene"
expect_error "file not found" --scene "$scene" --path "$work/missing.h5"
expect_error "--scene is required" --path "$work/path.h5"
expect_error "run folder not found" --scene "$scene" --run-dir "$work/no-such-run"
expect_error "unknown-flag" --scene "$scene" --unknown-flag
# Another schema: a labels artifact is not a path.
"$helper" labels "$scene" "$work/labels.h5"
expect_error "wrong schema (expected ausbau-path, got ausbau-labels)" --scene "$scene" --path "$work/labels.h5"

# --bench-dir: a page from ausbau-bench's files.
bench=$work/bench
mkdir -p "$bench"
cat > "$bench/summary.md" <<'MD'
# ausbau-bench: test

- Machine: test
- Command: `ausbau-bench --runs 2`

## Easy

| planner | success | median time (s) |
|---|---:|---:|
| CR-RRTC | 2/2 (100%) | **0.5** |
| OMPL default | 1/2 (50%) | 5 |

1. CR-RRTC success >= 95%: **met**.
   - Easy: 100%
MD
cat > "$bench/results.csv" <<'CSV'
scene,planner,seed,success,time_s,collision_checks,iterations,nodes,dense_check
Easy,CR-RRTC,1,1,0.4,100,10,10,ok
Easy,CR-RRTC,2,1,0.6,100,10,10,ok
Easy,OMPL default,1,1,2.0,100,0,10,ok
Easy,OMPL default,2,0,8.0,100,0,10,
CSV
printf '<?xml version="1.0" encoding="UTF-8"?>\n<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect id="heat-cell" width="5" height="5"/></svg>\n' \
  > "$bench/study-Easy.svg"
"$report" --bench-dir "$bench" -o "$work/bench.html" --log-level warn
for needle in '<table>' '<td style="text-align:right"><b>0.5</b></td>' 'id="heat-cell"' 'Easy: median time (s)' \
              '<code>ausbau-bench --runs 2</code>' '<ol><li>'; do
  grep -qF "$needle" "$work/bench.html" || fail "bench page lacks $needle"
done
grep -q '<?xml' "$work/bench.html" && fail "bench page repeats the SVG's XML declaration"
expect_error "no benchmark outputs" --bench-dir "$work/scene"
expect_error "takes no --scene" --bench-dir "$bench" --scene "$scene"

if [ "$failures" -ne 0 ]; then
  echo "check_report: $failures check(s) failed" >&2
  exit 1
fi
echo "check_report: all checks passed"
