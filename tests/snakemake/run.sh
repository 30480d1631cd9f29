#!/usr/bin/env bash
# pipelines/Snakefile end to end (ctest snakemake_batch):
#   tests/snakemake/run.sh BIN WORK
# Skipped (exit 77) where snakemake is not installed
# (scripts/install-deps.sh snakemake). In WORK (emptied first):
#  1. three generated rigid scenes (rod-in-cage, peg-in-plate, two-boxes) run
#     with --cores 2: every verdict removable, validity.txt rigid-exact (as
#     inistate.mk's VALIDITY=auto), two-boxes' path.csv byte-identical to
#     pipelines/inistate.mk's for the same seed;
#  2. run again: "Nothing to be done";
#  3. two-boxes' D moved by 1e-4 mm (every vertex rewritten): only two-boxes'
#     jobs run (plan among them, not from its cache), the other scenes' files
#     keep their modification times;
#     and SEED=2 (a dry run) reschedules plan for every scene;
#  4. rod-in-cage's plan forced (--forcerun): the stage answers from its cache
#     although Snakemake deleted path.h5 before the job;
#  5. VALIDITY=auto on a clips-ds1 scene (D intersects S) chooses labeled-mliv
#     and the dry run then schedules the volume chain; a blocked scene (D
#     inside S) ends with plan.status no-path, no smoothing and a
#     not-removable verdict (pipeline.exit 3);
#     (that dry run through the Slurm profile, pipelines/slurm: it parses);
#  6. bad config (an unknown VALIDITY) exits 2 with one line;
#  7. hostile names and links (issue 33, the rest in test_hostile_files):
#     a scene folder named like a command, and a link where a job writes
#     its log, exit 2 before any job, naming it; nothing runs or is written.
# The Slurm profile's jobs with stand-ins for sbatch and sacct: slurm.sh.
set -u
if [ $# -ne 2 ]; then
  echo "usage: $0 BIN WORK" >&2
  exit 2
fi
if ! command -v snakemake >/dev/null 2>&1; then
  echo "snakemake_batch: snakemake not installed (scripts/install-deps.sh snakemake): skipped"
  # CI (.ci/run) requires the Snakefile to be tested: there a missing
  # snakemake is a failure, not a skip.
  [ "${AUSBAU_REQUIRE_SNAKEMAKE:-0}" = 1 ] && { echo "snakemake_batch: AUSBAU_REQUIRE_SNAKEMAKE=1: failing" >&2; exit 1; }
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
# sm LOG [snakemake args...]: one snakemake run, its output in LOG.
sm() {
  local log=$1
  shift
  snakemake -s "$SNAKEFILE" "$@" > "$log" 2>&1
}
# scenes_that_ran LOG: the scene wildcard of every job the run executed.
scenes_that_ran() { sed -n 's/^ *wildcards: scene=\(.*\)$/\1/p' "$1" | sort -u | tr '\n' ' '; }
rules_that_ran() { sed -n 's/^\(local\)\{0,1\}\(rule\|checkpoint\) \([a-z_]*\):$/\3/p' "$1" | sort -u | tr '\n' ' '; }
snapshot() { find "$@" -type f ! -path '*/logs/*' -exec stat -c '%n %.9Y' {} + | sort; }

for family in rod-in-cage peg-in-plate two-boxes; do
  "$BIN/ausbau-scene-gen" --family "$family" --seed 1 -o "scenes/$family" --log-level error > /dev/null || exit 1
done
CONFIG=(--config SCENES=scenes OUT=out BIN="$BIN" THREADS=1 TIME_LIMIT=30)

# 1. The batch.
if ! sm run1.log --cores 2 "${CONFIG[@]}"; then
  fail "first run failed:"; tail -n 30 run1.log >&2
fi
for s in rod-in-cage peg-in-plate two-boxes; do
  grep -q '"status": "removable"' "out/$s/verdict.json" 2>/dev/null || fail "$s: verdict.json missing or not removable"
  [ "$(cat "out/$s/validity.txt" 2>/dev/null)" = rigid-exact ] || fail "$s: validity.txt is not rigid-exact"
  [ "$(cat "out/$s/pipeline.exit" 2>/dev/null)" = 0 ] || fail "$s: pipeline.exit is not 0"
  [ -s "out/$s/report.html" ] || fail "$s: no report.html"
done
grep -q 'batch: 3 of 3 scenes removable' out/verdicts.txt 2>/dev/null || fail "out/verdicts.txt does not count 3 of 3"
make -s -f "$REPO/pipelines/inistate.mk" SCENE=scenes/two-boxes/scene.yaml OUT=make/two-boxes BIN="$BIN" THREADS=1 \
  TIME_LIMIT=30 WITH_REPORT=0 > make.log 2>&1 || { fail "inistate.mk on two-boxes failed"; tail -n 20 make.log >&2; }
cmp -s make/two-boxes/path.csv out/two-boxes/path.csv || fail "two-boxes: path.csv differs from inistate.mk's"

# 2. Nothing changed: nothing runs.
sm run2.log --cores 2 "${CONFIG[@]}" || fail "second run failed"
grep -q 'Nothing to be done' run2.log || { fail "second run ran jobs: $(rules_that_ran run2.log)"; }

# 3. One part's mesh changed: only its scene's jobs run.
before=$(snapshot out/rod-in-cage out/peg-in-plate)
awk '$1 == "v" { printf "v %.17g %s %s\n", $2 + 0.0001, $3, $4; next } { print }' scenes/two-boxes/part.obj > part.obj.new &&
  mv part.obj.new scenes/two-boxes/part.obj
sm run3.log --cores 2 "${CONFIG[@]}" || fail "run after the mesh change failed"
ran=$(scenes_that_ran run3.log)
[ "$ran" = "two-boxes " ] || fail "after two-boxes' mesh changed, jobs ran for: '$ran' (expected two-boxes only)"
case " $(rules_that_ran run3.log)" in *" plan "*) ;; *) fail "plan did not run after two-boxes' mesh changed" ;; esac
grep -q 'is up to date' out/two-boxes/logs/plan.log && fail "two-boxes' plan answered from its cache after D changed"
grep -q '"status": "removable"' out/two-boxes/verdict.json 2>/dev/null || fail "two-boxes not removable after the change"
[ "$before" = "$(snapshot out/rod-in-cage out/peg-in-plate)" ] || fail "files of unchanged scenes were rewritten"

# 3b. An option changed: its jobs are scheduled (Snakemake's params), for every scene.
sm dry3.log -n --cores 2 "${CONFIG[@]}" SEED=2 || fail "dry run with SEED=2 failed"
[ "$(grep -c '^checkpoint plan:' dry3.log)" -eq 3 ] && [ "$(grep -c 'reason: Params have changed' dry3.log)" -ge 3 ] || fail "SEED=2: plan not rescheduled for the three scenes"

# 4. A job Snakemake reruns with unchanged inputs: the stage's cache answers.
sm run4.log --cores 2 "${CONFIG[@]}" --forcerun out/rod-in-cage/path.h5 || fail "forced run failed"
grep -q 'is up to date' out/rod-in-cage/logs/plan.log || fail "forced plan did not answer from the stage cache"
[ "$(scenes_that_ran run4.log)" = "rod-in-cage " ] || fail "forced rod-in-cage plan ran jobs for: $(scenes_that_ran run4.log)"

# 5. VALIDITY=auto choosing the volume chain; a blocked scene.
"$BIN/ausbau-scene-gen" --family clips-ds1 --seed 1 --triangles 500 -o more/clips --log-level error > /dev/null || exit 1
mkdir -p more/boxed && cp scenes/two-boxes/*.obj more/boxed/ &&
  sed 's/^start: .*/start: {t: [0, 0, 0], q: [1, 0, 0, 0]}/' scenes/two-boxes/scene.yaml > more/boxed/scene.yaml
MORE=(--config SCENES=more OUT=out-more BIN="$BIN" THREADS=1 TIME_LIMIT=5)
sm run5.log --cores 2 out-more/clips/validity.txt out-more/boxed/verdict.json "${MORE[@]}" ||
  { fail "run on clips and boxed failed"; tail -n 30 run5.log >&2; }
make_choice=$("$BIN/ausbau-plan" --scene more/clips/scene.yaml --choose-validity --rigid-tolerance 0.05 --log-level error)
[ "$make_choice" = labeled-mliv ] || fail "ausbau-plan --choose-validity on clips: '$make_choice' (the scene changed?)"
[ "$(cat out-more/clips/validity.txt 2>/dev/null)" = "$make_choice" ] || fail "clips: validity.txt is not $make_choice"
# The dry run goes through the Slurm profile (pipelines/slurm): it parses and
# schedules (sbatch is not called in a dry run).
sm dry5.log -n --profile "$REPO/pipelines/slurm" "${MORE[@]}" ||
  { fail "dry run with pipelines/slurm on clips failed"; tail -n 20 dry5.log >&2; }
for r in voxelize medial_spheres pbd_label distfield_build tau_estimate plan; do
  grep -q "^rule $r:\|^checkpoint $r:" dry5.log || fail "clips (labeled-mliv): the dry run does not schedule $r"
done
[ "$(cat out-more/boxed/plan.status 2>/dev/null)" = no-path ] || fail "boxed: plan.status is not no-path"
[ "$(cat out-more/boxed/pipeline.exit 2>/dev/null)" = 3 ] || fail "boxed: pipeline.exit is not 3"
grep -q '"status": "not-removable"' out-more/boxed/verdict.json 2>/dev/null || fail "boxed: verdict not not-removable"
grep -q '^rule smooth:' run5.log && fail "boxed: smoothing ran without a path"

# 6. Bad config: exit 2 and one line naming the key.
sm bad2.log -n --config SCENES=scenes OUT=x BIN="$BIN" VALIDITY=exact
[ $? -eq 2 ] && grep -q 'error: VALIDITY=exact' bad2.log || fail "VALIDITY=exact: not exit 2 with a message"

# 7. Hostile names and links: refused while the Snakefile is read.
mkdir -p hostile && cp -r scenes/two-boxes 'hostile/x$(touch${IFS}PWNED)'
sm bad3.log -n --config SCENES=hostile OUT=out-hostile BIN="$BIN"
[ $? -eq 2 ] && grep -qF "the folder name 'x\$(touch" bad3.log && [ ! -e PWNED ] && [ ! -e out-hostile ] ||
  fail "a scene folder named like a command: not exit 2 with a message, or it ran"
echo "the user's" > victim.txt && rm -f out/two-boxes/logs/plan.log && ln -s "$WORK/victim.txt" out/two-boxes/logs/plan.log
sm bad4.log -n "${CONFIG[@]}"
[ $? -eq 2 ] && grep -qF 'out/two-boxes/logs/plan.log is a symbolic link' bad4.log &&
  [ "$(cat victim.txt)" = "the user's" ] || fail "a link at a job's log: not exit 2 with a message, or written through"
rm -f out/two-boxes/logs/plan.log

if [ $failures -ne 0 ]; then
  echo "snakemake_batch: $failures failure(s); logs in $WORK" >&2
  exit 1
fi
echo "snakemake_batch: passed"
