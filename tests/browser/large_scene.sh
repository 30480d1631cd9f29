#!/usr/bin/env bash
# The report of a large scene (CTest: report_large_scene; also the numbers in
# stages/report/README.md):
#   tests/browser/large_scene.sh BIN_DIR WORK_DIR HELPER [TRIANGLES]
# S is a sphere shell of about TRIANGLES (default 100000) triangles, open at
# the top, D a rod of 2,028 triangles inside it. Plans and smooths the way out,
# writes the report and loads it in headless Chromium. Fails when the file is
# over 15 MB or the page is not ready within AUSBAU_REPORT_MAX_LOAD_S seconds
# (default 30: generous, the machine may be shared); prints size and times.
# Exit 77 (skip) where no Chromium can be installed, as run.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
usage="usage: large_scene.sh BIN_DIR WORK_DIR HELPER [TRIANGLES]"
bin=$(cd "${1:?$usage}" && pwd)
work=${2:?$usage}
helper=${3:?$usage}
triangles=${4:-100000}
max_load_s=${AUSBAU_REPORT_MAX_LOAD_S:-30}
mkdir -p "$work"
work=$(cd "$work" && pwd)

source "$here/setup.sh"  # sets $chromium and installs playwright-core (or exits 77)

run=$work/large
rm -rf "$run"
mkdir -p "$run"
"$helper" big-scene "$run/scene" "$triangles"
scene=$run/scene/scene.yaml
"$bin/ausbau-plan" --scene "$scene" --seed 1 --time-limit 120 -o "$run/path.h5" --log-level warn
"$bin/ausbau-smooth" --scene "$scene" --path "$run/path.h5" --seed 1 -o "$run/path-smooth.h5" --log-level warn
start=$(date +%s.%N)
"$bin/ausbau-report" --scene "$scene" --run-dir "$run" -o "$run/report.html" --log-level warn
end=$(date +%s.%N)
status=0
result=$(node "$here/report_test.js" --chromium "$chromium" --html "$run/report.html" \
  --screenshot "$work/report-large-$triangles.png" --path-key smoothed --timeout-ms $((max_load_s * 1000 + 30000))) || status=$?
echo "$result"
[ "$status" -eq 0 ] || exit "$status"
node - "$result" "$start" "$end" "$max_load_s" <<'JS'
const [result, start, end, maxLoadS] = process.argv.slice(2);
const r = JSON.parse(result);
const mb = r.sizeBytes / 1e6;
console.log(`report_large_scene: ${r.html}: ${mb.toFixed(2)} MB, written in ${(end - start).toFixed(2)} s; ` +
  `in headless Chromium (SwiftShader): ready ${(r.loadMs / 1000).toFixed(2)} s after navigation start, ` +
  `${(r.wallToReadyMs / 1000).toFixed(2)} s from goto() to ready`);
let ok = true;
if (mb > 15) { console.error(`report_large_scene: FAIL: ${mb.toFixed(2)} MB > 15 MB`); ok = false; }
if (r.loadMs / 1000 > Number(maxLoadS)) { console.error(`report_large_scene: FAIL: ready after ${r.loadMs} ms > ${maxLoadS} s`); ok = false; }
process.exit(ok ? 0 : 1);
JS
