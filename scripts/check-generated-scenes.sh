#!/usr/bin/env bash
# Generates the panel-* box scenes (ausbau-scene-gen, common/fixtures/box_scenes.h)
# into a temporary folder and judges them with the external benchmark set's
# exact checker (oracle.py, which reads boxes.json): each known path must
# pass (exit 0) and an obviously wrong path must fail (exit 1): a straight
# lift for panel-tilt-slide (the rail's foot is under a lip) and
# panel-channel (the tongue is under the roof), a pull 3 degrees off the
# panel normal for panel-straight-pull (four directions round the normal).
#   scripts/check-generated-scenes.sh [seed ...]      (default: 1 2)
# Every family, both tessellations, both world placements. Needs a built
# build/bin/ausbau-scene-gen; skips (exit 0, with a message) where python3
# has no numpy or the oracle is not there. Exit 1 when any check fails.
set -uo pipefail
cd "$(dirname "$0")/.."
python=${PYTHON:-/usr/bin/python3}
oracle=${ORACLE:-../shared/benchmarks/inistate-external/oracle.py}
gen=${BIN:-build/bin}/ausbau-scene-gen
seeds=("$@"); [ ${#seeds[@]} -eq 0 ] && seeds=(1 2)

if ! "$python" -c 'import numpy' 2>/dev/null; then
  echo "check-generated-scenes: skipped: $python has no numpy (apt-get install python3-numpy)"
  exit 0
fi
if [ ! -f "$oracle" ]; then
  echo "check-generated-scenes: skipped: no oracle at $oracle (set ORACLE)"
  exit 0
fi
[ -x "$gen" ] || { echo "check-generated-scenes: $gen not built" >&2; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Writes the wrong paths of a scene (wrong-*.csv beside scene.json) from its
# world placement and pull direction; prints their names.
wrong_paths() {
  "$python" - "$1" <<'EOF'
import csv, json, math, os, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, 'scene.json')))
w, x, y, z = s['world_placement']['q_wxyz']
R = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
ex, ey = [R[i][0] for i in range(3)], [R[i][1] for i in range(3)]  # the design frame's x and y
n = s['pull_direction_world']
rows = list(csv.reader(open(os.path.join(d, 'truth', 'known_path.csv'))))
length = math.sqrt(sum(float(v) ** 2 for v in rows[-1][:3]))  # how far the known path ends
if s['family'] == 'panel-straight-pull':
    off = math.radians(3.0)
    dirs = {}
    for az in (0.0, 22.5, 45.0, 67.5):
        a = math.radians(az)
        dirs['off3-az%g' % az] = [math.cos(off) * n[i] + math.sin(off) * (math.cos(a) * ex[i] + math.sin(a) * ey[i])
                                  for i in range(3)]
else:
    dirs = {'straight-lift': n}
for name, v in dirs.items():
    with open(os.path.join(d, 'wrong-%s.csv' % name), 'w') as f:
        f.write('x,y,z,qw,qx,qy,qz\n0,0,0,1,0,0,0\n')
        f.write('%.12g,%.12g,%.12g,1,0,0,0\n' % tuple(length * c for c in v))
    print('wrong-%s.csv' % name)
EOF
}

failed=0
printf '%-20s %4s %-7s %-8s %-6s %s\n' family seed tess world known wrong
for family in panel-tilt-slide panel-straight-pull panel-channel; do
  for seed in "${seeds[@]}"; do
    for tess in coarse fine; do
      for world in identity random; do
        dir=$tmp/$family-$seed-$tess-$world
        if ! "$gen" --family "$family" --seed "$seed" --tessellation "$tess" --world "$world" -o "$dir" \
             >/dev/null 2>"$tmp/gen.err"; then
          printf '%-20s %4s %-7s %-8s %s\n' "$family" "$seed" "$tess" "$world" "GENERATION FAILED: $(cat "$tmp/gen.err")"
          failed=1
          continue
        fi
        "$python" "$oracle" "$dir" "$dir/truth/known_path.csv" --compact >"$dir/known.json" 2>&1
        known=$?
        [ $known -eq 0 ] || failed=1
        wrong=""
        for csv in $(wrong_paths "$dir"); do
          "$python" "$oracle" "$dir" "$dir/$csv" --compact --fail-fast >"$dir/$csv.json" 2>&1
          rc=$?
          [ $rc -eq 1 ] || failed=1
          wrong+="${csv%.csv}=$rc "
        done
        printf '%-20s %4s %-7s %-8s %-6s %s\n' "$family" "$seed" "$tess" "$world" "$known" "$wrong"
      done
    done
  done
done
if [ $failed -ne 0 ]; then
  echo "check-generated-scenes: FAILED (known paths must exit 0, wrong paths 1)"
  exit 1
fi
echo "check-generated-scenes: all known paths valid, all wrong paths rejected"
