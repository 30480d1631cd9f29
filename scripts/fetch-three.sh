#!/usr/bin/env bash
# Fetches three.js from the npm registry into DIR (build time, for
# ausbau-report, which embeds it into its executable).
#   scripts/fetch-three.sh DIR [VERSION]     default VERSION 0.160.1
# Leaves DIR/node_modules/three/build/three.module.min.js and
# DIR/node_modules/three/examples/jsm/controls/OrbitControls.js, and the stamp
# file DIR/three-VERSION.stamp.
set -euo pipefail
dir=${1:?usage: fetch-three.sh DIR [VERSION]}
version=${2:-0.160.1}
if ! command -v npm >/dev/null; then
  echo "fetch-three: error: npm not found; install it with 'apt-get install nodejs npm' (or scripts/install-deps.sh)" >&2
  exit 2
fi
mkdir -p "$dir"
cd "$dir"
# A package.json of its own, so that npm installs here and not into a parent.
[ -f package.json ] || echo '{"name": "ausbau-three", "private": true}' > package.json
rm -f three-*.stamp
if ! npm install --no-save --no-audit --no-fund --loglevel=error "three@$version" >npm.log 2>&1; then
  cat npm.log >&2
  echo "fetch-three: error: 'npm install three@$version' failed (is the npm registry reachable?)" >&2
  exit 1
fi
for f in node_modules/three/build/three.module.min.js node_modules/three/examples/jsm/controls/OrbitControls.js; do
  [ -s "$f" ] || { echo "fetch-three: error: three@$version does not ship $f" >&2; exit 1; }
done
got=$(node -p "require('./node_modules/three/package.json').version" 2>/dev/null || echo "$version")
echo "$got" > "three-$version.stamp"
