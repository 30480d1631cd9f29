#!/usr/bin/env bash
# End-to-end test of the installed tree and the Debian package (CTest:
# install_and_package):
#   tests/install/check_install.sh BUILD_DIR WORK_DIR
# 1. cmake --install into WORK_DIR/prefix: the stages, ausbau-run, the
#    pipelines, their scripts and the docs are where cmake/AusbauInstall.cmake
#    says; the installed stages run.
# 2. ausbau-run (installed, from another working folder) on a generated
#    scene: exit 0 and verdict.json removable; on a part sealed in a box:
#    exit 3 (not removable), on a missing scene: exit 2.
# 3. cpack -G DEB: the package holds the same tree under /usr, and its
#    stages run from an extracted copy (dpkg-deb -x; not installed on the
#    machine).
set -euo pipefail
usage="usage: check_install.sh BUILD_DIR WORK_DIR"
build=$(cd "${1:?$usage}" && pwd)
work=${2:?$usage}
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)
fail() { echo "check_install: FAIL: $*" >&2; exit 1; }

prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in bin/ausbau-plan bin/ausbau-smooth bin/ausbau-verdict bin/ausbau-report bin/ausbau-assembly bin/ausbau-scene-gen \
         bin/ausbau-run share/ausbau/pipelines/inistate.mk share/ausbau/pipelines/step.mk share/ausbau/pipelines/Snakefile \
         share/ausbau/scripts/timed.sh share/ausbau/scripts/verdict-table.sh share/ausbau/scenes/panel-tilt-slide-1/scene.yaml \
         share/doc/ausbau/README.md share/doc/ausbau/stages/plan.md share/doc/ausbau/schemas/scene.md; do
  [ -e "$prefix/$f" ] || fail "$f not installed"
done
[ -x "$prefix/bin/ausbau-run" ] || fail "ausbau-run not executable"
"$prefix/bin/ausbau-plan" --version | grep -q . || fail "installed ausbau-plan does not run"
"$prefix/bin/ausbau-run" --version | grep -q '^ausbau-run ' || fail "installed ausbau-run --version"

# 2. ausbau-run, from a folder that is neither the source nor the build tree.
cd "$work"
"$prefix/bin/ausbau-scene-gen" --family two-boxes --seed 1 -o "$work/free" --log-level warn
set +e
"$prefix/bin/ausbau-run" "$work/free/scene.yaml" "$work/free-run" TIME_LIMIT=30 > "$work/free.log" 2>&1
status=$?
set -e
[ $status -eq 0 ] || { tail -20 "$work/free.log"; fail "ausbau-run on two-boxes exited $status (expected 0)"; }
grep -Eq '"removable"[[:space:]]*:[[:space:]]*true' "$work/free-run/verdict.json" || fail "two-boxes not removable"

# A unit cube sealed in a hollow box (0.5 mm of air on every side): no way out.
mkdir -p "$work/sealed"
cube() {  # cube LO HI FLIP: the 12 triangles of [LO, HI]^3, outward (FLIP=0) or inward (1), vertices from $3+1
  local lo=$1 hi=$2 flip=$3 base=$4
  for z in "$lo" "$hi"; do for y in "$lo" "$hi"; do for x in "$lo" "$hi"; do echo "v $x $y $z"; done; done; done
  local faces=("1 3 4 2" "5 6 8 7" "1 2 6 5" "3 7 8 4" "1 5 7 3" "2 4 8 6")
  for f in "${faces[@]}"; do
    set -- $f
    local a=$(($1 + base)) b=$(($2 + base)) c=$(($3 + base)) d=$(($4 + base))
    if [ "$flip" = 0 ]; then echo "f $a $b $c"; echo "f $a $c $d"; else echo "f $a $c $b"; echo "f $a $d $c"; fi
  done
}
cube 0 1 0 0 > "$work/sealed/part.obj"
{ cube -1 2 0 0; cube -0.5 1.5 1 8; } > "$work/sealed/box.obj"
cat > "$work/sealed/scene.yaml" <<'YAML'
format: ausbau-scene/1
name: "sealed"
units: "mm"
static: ["box.obj"]
dynamic: "part.obj"
dynamic_origin: [0.5, 0.5, 0.5]
start: {t: [0.5, 0.5, 0.5], q: [1, 0, 0, 0]}
bounds: {min: [-4, -4, -4], max: [5, 5, 5]}
YAML
set +e
"$prefix/bin/ausbau-run" "$work/sealed/scene.yaml" "$work/sealed-run" TIME_LIMIT=2 > "$work/sealed.log" 2>&1
status=$?
"$prefix/bin/ausbau-run" "$work/missing/scene.yaml" "$work/missing-run" > "$work/missing.log" 2>&1
missing=$?
set -e
[ $status -eq 3 ] || { tail -20 "$work/sealed.log"; fail "ausbau-run on a sealed part exited $status (expected 3)"; }
[ $missing -eq 2 ] || { tail -20 "$work/missing.log"; fail "ausbau-run on a missing scene exited $missing (expected 2)"; }

# 3. The Debian package.
if ! command -v cpack > /dev/null || ! command -v dpkg-deb > /dev/null; then
  echo "check_install: cpack or dpkg-deb missing: package not checked" >&2
  exit 0
fi
(cd "$build" && cpack -G DEB -B "$work/package" > "$work/cpack.log" 2>&1) || { tail -20 "$work/cpack.log"; fail "cpack -G DEB"; }
deb=$(ls "$work"/package/ausbau_*.deb)
dpkg-deb --info "$deb" > "$work/deb-info.txt"
grep -q '^ Package: ausbau' "$work/deb-info.txt" || fail "package name"
grep -q '^ Depends:.*make' "$work/deb-info.txt" || fail "package does not depend on make"
grep -q '^ Depends:.*libassimp' "$work/deb-info.txt" || fail "package does not depend on the shared libraries (dpkg-shlibdeps)"
dpkg-deb -x "$deb" "$work/extracted"
[ -x "$work/extracted/usr/bin/ausbau-run" ] || fail "ausbau-run not in the package"
[ -f "$work/extracted/usr/share/ausbau/pipelines/inistate.mk" ] || fail "pipelines not in the package"
"$work/extracted/usr/bin/ausbau-verdict" --version | grep -q . || fail "packaged ausbau-verdict does not run"
echo "check_install: installed tree, ausbau-run (exit 0, 3, 2) and $(basename "$deb"): ok"
