#!/usr/bin/env bash
# Installs the Debian packages Ausbau needs, only those that are missing.
# Called by `make demo` and `make test`; safe to run again.
#   scripts/install-deps.sh         the packages every build needs
#   scripts/install-deps.sh bench   those plus libompl-dev (OMPL 1.5, for
#                                   ausbau-bench: `make bench`, `make study`)
#   scripts/install-deps.sh browser those plus chromium (headless browser for
#                                   the report's browser test: `make test`)
#   scripts/install-deps.sh fuzz    those plus clang and libFuzzer (the
#                                   harnesses in fuzz/: `make fuzz`)
#   scripts/install-deps.sh format  those plus clang-format 14 (the style
#                                   check: `make format-check`, .ci/run)
#   scripts/install-deps.sh snakemake  those plus Snakemake 7 (batches
#                                   locally or on Slurm: pipelines/Snakefile,
#                                   `make snakemake`; about 80 Python
#                                   packages, so not in the default set)
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  dpkg-dev  # dpkg-shlibdeps: the Debian package's dependencies (make package)
  libeigen3-dev libfcl-dev libassimp-dev libhdf5-dev hdf5-tools
  libyaml-cpp-dev libcli11-dev libgtest-dev libxxhash-dev
  libcgal-dev  # header-only; the test fixtures' welded unions (moulded twins)
  # OpenCASCADE: STEP assemblies (ausbau-assembly), their product tree (XCAF)
  libocct-data-exchange-dev libocct-ocaf-dev libocct-modeling-algorithms-dev
  libtbb-dev  # named by OpenCASCADE's CMake targets, not pulled in by its -dev packages
  nodejs npm
)
case "${1:-}" in
  "") ;;
  bench) packages+=(libompl-dev) ;;
  browser) packages+=(chromium) ;;
  fuzz) packages+=(clang libfuzzer-14-dev libclang-rt-14-dev libomp-14-dev) ;;
  format) packages+=(clang-format-14) ;;
  snakemake) packages+=(snakemake) ;;
  *) echo "install-deps: error: unknown argument '$1' (expected nothing, 'bench', 'browser', 'format', 'fuzz' or 'snakemake')" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  # node and npm may come from elsewhere (NodeSource's nodejs ships npm, and
  # Debian's npm conflicts with it): a working command is enough.
  case "$p" in nodejs) command -v node >/dev/null && continue ;; npm) command -v npm >/dev/null && continue ;; esac
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then sudo="sudo"; else
    echo "install-deps: error: need root (or sudo) to install: ${missing[*]}" >&2; exit 2
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
