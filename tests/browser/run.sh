#!/usr/bin/env bash
# End-to-end test of ausbau-report in a real browser (CTest: report_in_browser).
#   tests/browser/run.sh BIN_DIR WORK_DIR HELPER
# Generates the rod-in-cage scene (D's mesh moved off its origin by the
# helper, so that the reference point differs from dynamic_origin), plans and
# smooths it, writes the report, opens it in headless Chromium
# (tests/browser/report_test.js through playwright-core, installed from npm
# into WORK_DIR at the first run) and checks: no console error, no request
# outside the file, S and D drawn, D at the waypoints and on the path.md
# interpolation between them, the scrubber moves D, Play advances; then a
# second report with labels.h5 and verdict.json in the run folder: D coloured,
# verdict table; then the demo's run (pipelines/inistate.mk on
# scenes/panel-tilt-slide-1, as `make demo`): its headline against its
# verdict.json, the three plots, the waypoint table with parts named after
# the mesh files, the section plane, the measurement and the download of
# path.csv. On every report: the headline's numbers carry units; the view is
# upright for the scene's up axis (the OBJ/STL scenes by default z, a copy of
# the scene with `up_axis: y` the key's). On the labels' and the demo's
# report also: no sideways scroll at 1280x720 and 1366x768 with the verdict
# table fitting, and in a Chromium without WebGL the sentence in the 3D area
# with the plots and tables all there. Leaves screenshots WORK_DIR/report.png,
# report-labels.png, report-labels-nowebgl.png, report-demo.png,
# report-demo-nowebgl.png.
# Exit 77 (CTest's SKIP_RETURN_CODE) when no Chromium is installed and none
# can be installed (`scripts/install-deps.sh browser`, which `make test` runs).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
usage="usage: run.sh BIN_DIR WORK_DIR HELPER"
bin=$(cd "${1:?$usage}" && pwd)
work=${2:?$usage}
helper=${3:?$usage}
mkdir -p "$work"
work=$(cd "$work" && pwd)

source "$here/setup.sh"  # sets $chromium and installs playwright-core (or exits 77)

run=$work/run
rm -rf "$run"
mkdir -p "$run"
"$bin/ausbau-scene-gen" --family rod-in-cage --seed 1 -o "$run/generated" >/dev/null
"$helper" offset "$run/generated/scene.yaml" "$run/scene" 5 3 -2
scene=$run/scene/scene.yaml
"$bin/ausbau-plan" --scene "$scene" --seed 1 --time-limit 60 -o "$run/path.h5" --csv "$run/path.csv" --log-level warn
"$bin/ausbau-smooth" --scene "$scene" --path "$run/path.h5" --seed 1 -o "$run/path-smooth.h5" \
  --csv "$run/path-smooth.csv" --log-level warn
"$bin/ausbau-report" --scene "$scene" --run-dir "$run" -o "$run/report.html" --log-level warn

# The reference point and dynamic_origin, read independently of ausbau-report.
vector() { h5dump -m "%.17g" -d "/$1" -y -w 0 "$2" | awk '/DATA \{/ { getline; gsub(/[ \t]/, ""); print; exit }'; }
ref=$(vector reference_point "$run/path-smooth.h5")
origin=$(vector dynamic_origin "$run/path-smooth.h5")
echo "report_in_browser: reference point $ref, dynamic_origin $origin"
[ "$ref" != "$origin" ] || { echo "report_in_browser: error: the test scene should have reference point != dynamic_origin" >&2; exit 1; }

node "$here/report_test.js" --chromium "$chromium" --html "$run/report.html" --screenshot "$work/report.png" \
  --csv "$run/path-smooth.csv" --ref "$ref" --origin "$origin" --path-key smoothed --expect-headline "NO VERDICT" \
  --expect-up z --expect-up-source "default for OBJ/STL/STEP data"
node "$here/report_test.js" --chromium "$chromium" --html "$run/report.html" --screenshot "$work/report-planned.png" \
  --csv "$run/path.csv" --ref "$(vector reference_point "$run/path.h5")" \
  --origin "$(vector dynamic_origin "$run/path.h5")" --path-key planned

# Labels and a verdict in the run folder; the scene's `up_axis` key (y,
# against the default z of its OBJ files).
mkdir -p "$run/labeled"
cp "$scene" "$run/scene/scene-y-up.yaml"
echo 'up_axis: y' >> "$run/scene/scene-y-up.yaml"
cp "$run/path.h5" "$run/path-smooth.h5" "$run/labeled/"
"$helper" labels "$scene" "$run/labeled/labels.h5"
echo '{"status": "removable", "checks": {"collision_free": true, "min_clearance": 0.0035}, "notes": ["test"]}' \
  > "$run/labeled/verdict.json"
"$bin/ausbau-report" --scene "$run/scene/scene-y-up.yaml" --run-dir "$run/labeled" -o "$run/report-labels.html" \
  --log-level warn
node "$here/report_test.js" --chromium "$chromium" --html "$run/report-labels.html" \
  --screenshot "$work/report-labels.png" --load-only --expect-labels --expect-table json-verdict \
  --expect-headline REMOVABLE --expect-up y --expect-up-source "scene key" --check-layout --check-no-webgl

# The demo's run, as `make demo` makes it.
repo=$(cd "$here/../.." && pwd)
demo=$run/demo
if ! make --no-print-directory -f "$repo/pipelines/inistate.mk" SCENE="$repo/scenes/panel-tilt-slide-1/scene.yaml" \
     OUT="$demo" BIN="$bin" SEED=1 > "$work/demo.log" 2>&1; then
  grep -q '"removable"' "$demo/verdict.json" 2>/dev/null || { cat "$work/demo.log" >&2; exit 1; }
fi
# The verdict, read independently of ausbau-report.
if grep -Eq '"removable"[[:space:]]*:[[:space:]]*true' "$demo/verdict.json"; then word=REMOVABLE; else word="NOT REMOVABLE"; fi
node "$here/report_test.js" --chromium "$chromium" --html "$demo/report.html" --screenshot "$work/report-demo.png" \
  --csv "$demo/path.csv" --ref "$(vector reference_point "$demo/path-smooth.h5")" \
  --origin "$(vector dynamic_origin "$demo/path-smooth.h5")" --path-key smoothed --expect-headline "$word" \
  --expect-part static.stl --expect-table json-verdict --expect-up z --check-layout --check-no-webgl
echo "report_in_browser: passed; screenshots $work/report.png, $work/report-labels.png, $work/report-demo.png"
