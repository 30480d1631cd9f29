#!/usr/bin/env bash
# pipelines/slurm (the Snakemake profile for Slurm) end to end, without a
# cluster (ctest snakemake_slurm):
#   tests/snakemake/slurm.sh BIN WORK
# Skipped (exit 77) where snakemake is not installed. In WORK (emptied
# first), with stand-ins for sbatch and sacct: a generated scene's four jobs
# (choose_validity, plan, smooth, verdict) are submitted with their
# resources, each runs through its own snakemake, the verdict is removable;
# status.sh maps sacct's states to Snakemake's.
set -u
if [ $# -ne 2 ]; then
  echo "usage: $0 BIN WORK" >&2
  exit 2
fi
if ! command -v snakemake >/dev/null 2>&1; then
  echo "snakemake_slurm: snakemake not installed (scripts/install-deps.sh snakemake): skipped"
  # CI (.ci/run) requires the Snakefile to be tested: there a missing
  # snakemake is a failure, not a skip.
  [ "${AUSBAU_REQUIRE_SNAKEMAKE:-0}" = 1 ] && { echo "snakemake_slurm: AUSBAU_REQUIRE_SNAKEMAKE=1: failing" >&2; exit 1; }
  exit 77
fi
BIN=$(cd "$1" && pwd) || exit 2
REPO=$(cd "$(dirname "$0")/../.." && pwd)
SNAKEFILE=$REPO/pipelines/Snakefile
WORK=$2
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" && WORK=$(pwd) || exit 1
failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}
sm() {
  local log=$1
  shift
  snakemake -s "$SNAKEFILE" "$@" > "$log" 2>&1
}
"$BIN/ausbau-scene-gen" --family two-boxes --seed 1 -o scenes/two-boxes --log-level error > /dev/null || exit 1

# The Slurm profile with stand-ins for sbatch (runs the job script here,
# in the background) and sacct (the job's state from its exit status, or
# FAKE_STATE): a scene's jobs go through sbatch, each job's own snakemake
# (--mode 2, where the checkpoints are not in its DAG) and status.sh; then
# status.sh's mapping of sacct's states.
mkdir -p fake-bin fake-slurm
cat > fake-bin/sbatch <<'EOF_SBATCH'
#!/bin/bash
id=$(( $(cat "$FAKE_SLURM/next" 2>/dev/null || echo 100) + 1 ))
echo $id > "$FAKE_SLURM/next"
printf '%s\n' "$*" >> "$FAKE_SLURM/sbatch.log"
( bash "${@: -1}" > "$FAKE_SLURM/$id.out" 2>&1; echo $? > "$FAKE_SLURM/$id.rc" ) > /dev/null 2>&1 &
echo $id
EOF_SBATCH
cat > fake-bin/sacct <<'EOF_SACCT'
#!/bin/bash
if [ -n "${FAKE_STATE+set}" ]; then echo "$FAKE_STATE"; exit 0; fi
while [ $# -gt 0 ]; do [ "$1" = -j ] && id=$2; shift; done
rc=$(cat "$FAKE_SLURM/$id.rc" 2>/dev/null) || { echo RUNNING; exit 0; }
if [ "$rc" = 0 ]; then echo COMPLETED; else echo FAILED; fi
EOF_SACCT
chmod +x fake-bin/sbatch fake-bin/sacct
# A fresh scene: choose_validity, plan, smooth, verdict as four jobs; smooth
# and verdict are created after their checkpoints finished, the case where a
# job's own snakemake once got <TBD> inputs.
SLURM=(--config SCENE_LIST=scenes/two-boxes/scene.yaml OUT=out-slurm BIN="$BIN" THREADS=1 WITH_REPORT=0)
# CI=true: Snakemake 7 then polls the cluster every second instead of every 10 s.
PATH="$WORK/fake-bin:$PATH" FAKE_SLURM="$WORK/fake-slurm" CI=true sm jobs.log --profile "$REPO/pipelines/slurm" \
  --latency-wait 5 "${SLURM[@]}" || { fail "two-boxes through pipelines/slurm failed"; tail -n 20 jobs.log fake-slurm/*.out >&2; }
for r in choose_validity plan smooth verdict; do
  grep -q -- "--job-name=ausbau-$r " fake-slurm/sbatch.log 2>/dev/null || fail "pipelines/slurm: $r was not submitted"
done
grep -q -- '--job-name=ausbau-verdict --cpus-per-task=1 --mem=4000 --time=30' fake-slurm/sbatch.log 2>/dev/null ||
  fail "pipelines/slurm: the verdict job's sbatch line lacks its resources"
grep -q '"status": "removable"' out-slurm/two-boxes/verdict.json 2>/dev/null || fail "two-boxes through pipelines/slurm: no verdict"
for pair in COMPLETED:success TIMEOUT:failed OUT_OF_MEMORY:failed "CANCELLED by 12:failed" RUNNING:running PENDING:running :running; do
  state=${pair%:*} want=${pair##*:}
  got=$(PATH="$WORK/fake-bin:$PATH" FAKE_STATE=$state "$REPO/pipelines/slurm/status.sh" '4242;cluster')
  [ "$got" = "$want" ] || fail "status.sh: sacct state '$state' gave '$got', expected '$want'"
done

if [ $failures -ne 0 ]; then
  echo "snakemake_slurm: $failures failure(s); logs in $WORK" >&2
  exit 1
fi
echo "snakemake_slurm: passed"
