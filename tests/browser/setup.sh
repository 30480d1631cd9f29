# Sourced by the browser tests (run.sh, large_scene.sh) with $work set:
# finds Chromium (or exits 77, CTest's skip code, saying why) and installs
# playwright-core from npm into $work/node_modules (no browser download: it
# drives the system's Chromium).
AUSBAU_PLAYWRIGHT_VERSION=${AUSBAU_PLAYWRIGHT_VERSION:-1.65.1}

chromium=${AUSBAU_CHROMIUM:-}
if [ -z "$chromium" ]; then
  for candidate in chromium chromium-browser google-chrome; do
    if command -v "$candidate" >/dev/null; then chromium=$(command -v "$candidate"); break; fi
  done
fi
if [ -z "$chromium" ] && [ -x "$here/../../scripts/install-deps.sh" ] && [ "$(id -u)" -eq 0 ]; then
  echo "browser test: no Chromium found; installing it (scripts/install-deps.sh browser)" >&2
  "$here/../../scripts/install-deps.sh" browser >&2 || true
  command -v chromium >/dev/null && chromium=$(command -v chromium)
fi
if [ -z "$chromium" ]; then
  echo "SKIPPED: no Chromium could be found or installed (install it with 'scripts/install-deps.sh browser'" \
       "or 'apt-get install chromium', or set AUSBAU_CHROMIUM=/path/to/chrome)" >&2
  exit 77
fi
for tool in node npm h5dump; do
  command -v "$tool" >/dev/null || { echo "browser test: error: $tool not found (scripts/install-deps.sh)" >&2; exit 1; }
done

if [ "$(node -p "try { require('$work/node_modules/playwright-core/package.json').version } catch (e) { '' }")" \
     != "$AUSBAU_PLAYWRIGHT_VERSION" ]; then
  [ -f "$work/package.json" ] || echo '{"name": "ausbau-browser-test", "private": true}' > "$work/package.json"
  if ! (cd "$work" && npm install --no-save --no-audit --no-fund --loglevel=error \
        "playwright-core@$AUSBAU_PLAYWRIGHT_VERSION" >npm.log 2>&1); then
    cat "$work/npm.log" >&2
    echo "browser test: error: npm install playwright-core@$AUSBAU_PLAYWRIGHT_VERSION failed" >&2
    exit 1
  fi
fi
export NODE_PATH="$work/node_modules"
