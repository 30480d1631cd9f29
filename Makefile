# Ausbau: the two commands a new user needs.
#   make demo   installs what is missing (Debian packages), builds, and runs
#               the InIState pipeline on a shipped clip scene: is the part
#               removable, along which path (prints the verdict)
#   make test   the same set-up, then the whole test suite
# And for your own scenes (docs/pipelines.md "Running the InIState pipeline"):
#   make run SCENE=path/to/scene.yaml OUT=dir     one scene (pipelines/inistate.mk)
#   make batch SCENES=dir OUT=dir [-j N]          every dir/*/scene.yaml, then a table
#   make snakemake SCENES=dir OUT=dir [CORES=N | PROFILE=pipelines/slurm]
#                                                 the same through Snakemake (pipelines/Snakefile), locally or on Slurm
#   make step STEP=assembly.step OUT=dir [-j N]   a STEP assembly: a scene per part, every part's verdict (pipelines/step.mk)
#   make demo-rigid                               the rigid planning demo (pipelines/plan.mk)
# Everything builds into build/; stage executables land in build/bin/.

BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= out/demo
DEMO_SCENE ?= scenes/panel-tilt-slide-1/scene.yaml
# The external benchmark set's exact checker, used by the demo where it is there.
ORACLE ?= ../shared/benchmarks/inistate-external/oracle.py
DEMO_RIGID_OUT ?= out/demo-rigid
SEED ?= 1
# A word for the shell, whatever it holds: every file or folder name a
# recipe passes on goes through it (a name like `a;touch x` or `o ut` must
# arrive as one argument, not run or split); the pipelines themselves then
# refuse names they cannot pass on safely (pipelines/safe-names.mk).
quote = '$(subst ','\'',$(1))'

# Benchmarks (need OMPL: `scripts/install-deps.sh bench` adds libompl-dev).
#   make bench   Ausbau's planners side by side with OMPL's RRT-Connect on the
#                OMPL.app scenes; with the defaults this takes hours (at most
#                scenes x configurations x runs x time limit, about 7 h)
#   make study   the RRTC parameter study (thesis 3.3.1): 90 cells x runs, each
#                run at most STUDY_TIME_LIMIT s, so up to 75 min per scene
BENCH_RUNS ?= 10
BENCH_TIME_LIMIT ?= 60
BENCH_SCENES ?=
BENCH_OUT ?= out/bench
BENCH_ARGS ?=
STUDY_RUNS ?= 5
STUDY_TIME_LIMIT ?= 10
STUDY_SCENES ?= alpha-1.5,Easy
STUDY_OUT ?= out/study
STUDY_ARGS ?=

.PHONY: all deps configure build demo demo-rigid run batch step test clean bench-deps bench-build bench study fuzz install package
.DELETE_ON_ERROR:

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(call quote,$(BUILD)) -DCMAKE_BUILD_TYPE=Release > /dev/null

build: configure
	@cmake --build $(call quote,$(BUILD)) -j $(call quote,$(JOBS))

# The InIState pipeline on the shipped panel scene (scenes/panel-tilt-slide-1,
# written by `ausbau-scene-gen --family panel-tilt-slide --seed 1`: a box-soup
# trim panel metres from the origin, clips, a rail under a lip, a locating
# pin), then path.csv checked by an independent checker where there is one:
# the external set's oracle.py (boxes.json scenes) or, for the clips-ds*
# scenes (DEMO_SCENE=scenes/clips-ds1/scene.yaml: VALIDITY=auto picks labeled-mliv), the
# generator's ground truth. A link at OUT/oracle.json is refused (as the
# pipeline refuses links at its own paths), and the file is written with
# noclobber, so its target is never written.
demo: build
	@$(MAKE) --no-print-directory -f pipelines/inistate.mk $(call quote,SCENE=$(DEMO_SCENE)) $(call quote,OUT=$(DEMO_OUT)) \
	  $(call quote,BIN=$(BUILD)/bin) $(call quote,SEED=$(SEED))
	@if [ -x $(call quote,$(BUILD)/bin/ausbau-check-path) ] && [ -f $(call quote,$(dir $(DEMO_SCENE))ground_truth.yaml) ]; then \
	  printf 'demo: against the ground truth: '; $(call quote,$(BUILD)/bin/ausbau-check-path) --scene $(call quote,$(DEMO_SCENE)) \
	    --ground-truth $(call quote,$(dir $(DEMO_SCENE))ground_truth.yaml) --path $(call quote,$(DEMO_OUT)/path-smooth.h5) 2>/dev/null; fi
	@if [ -f $(call quote,$(dir $(DEMO_SCENE))boxes.json) ] && [ -f $(call quote,$(ORACLE)) ] && /usr/bin/python3 -c 'import numpy' 2>/dev/null; then \
	  if [ -L $(call quote,$(DEMO_OUT)/oracle.json) ]; then \
	    printf 'demo: %s/oracle.json is a symbolic link; the demo writes only its own files inside OUT\n' $(call quote,$(DEMO_OUT)) >&2; exit 2; fi; \
	  rm -f $(call quote,$(DEMO_OUT)/oracle.json); \
	  if (set -C; /usr/bin/python3 $(call quote,$(ORACLE)) $(call quote,$(dir $(DEMO_SCENE))) $(call quote,$(DEMO_OUT)/path.csv) > $(call quote,$(DEMO_OUT)/oracle.json)); then \
	    printf 'demo: %s: path.csv valid\n' $(call quote,$(ORACLE)); \
	  else printf 'demo: %s: path.csv INVALID (%s/oracle.json)\n' $(call quote,$(ORACLE)) $(call quote,$(DEMO_OUT)); exit 1; fi; fi
	@printf 'demo: verdict %s/verdict.json (printed above); path %s/path.csv (smoothed, x,y,z,qw,qx,qy,qz)\n' \
	  $(call quote,$(DEMO_OUT)) $(call quote,$(DEMO_OUT))
	@printf 'demo: report: %s/report.html (one self-contained HTML file: open it in a browser)\n' $(call quote,$(DEMO_OUT))

# The rigid planning demo: a rod in a cage, plan -> smooth -> report.
demo-rigid: build
	@$(MAKE) --no-print-directory -f pipelines/plan.mk $(call quote,SCENE=$(DEMO_RIGID_OUT)/scene/scene.yaml) \
	  $(call quote,OUT=$(DEMO_RIGID_OUT)) $(call quote,BIN=$(BUILD)/bin) $(call quote,SEED=$(SEED)) generate-demo-scene all
	@printf 'demo-rigid: path written to %s/path.csv (smoothed: %s/path-smooth.csv)\n' \
	  $(call quote,$(DEMO_RIGID_OUT)) $(call quote,$(DEMO_RIGID_OUT))
	@printf 'demo-rigid: report: %s/report.html (one self-contained HTML file: open it in a browser)\n' $(call quote,$(DEMO_RIGID_OUT))

# One scene through the InIState pipeline; any pipeline variable (SEED,
# TIME_LIMIT, VALIDITY, PLAN_FLAGS, PLAN=..., see pipelines/inistate.mk) can
# be given on the command line. OUT defaults to out/run/<scene folder>.
# GNU make exits 2 for any failed recipe, so `make run` exits 0 removable
# and 2 otherwise, and says which; for scripts, build/bin/ausbau-run
# SCENE OUT exits 3 for not removable and 2 for bad input (README "What the verdict means", exit codes).
run: build
	@test -n $(call quote,$(SCENE)) || { echo "make run: SCENE=path/to/scene.yaml is required" >&2; exit 2; }
	@$(call quote,$(BUILD)/bin/ausbau-run) $(call quote,$(SCENE)) $(call quote,$(or $(OUT),out/run/$(notdir $(patsubst %/,%,$(dir $(SCENE)))))) \
	  || { status=$$?; [ $$status -eq 3 ] && echo "make run: not removable (ausbau-run exits 3; make itself only 2)" >&2; exit $$status; }

# Installs the stages, ausbau-run, the pipelines and the docs under PREFIX
# (default /usr/local; cmake/AusbauInstall.cmake says what goes where).
PREFIX ?= /usr/local
install: build
	cmake --install $(call quote,$(BUILD)) --prefix $(call quote,$(PREFIX))

# The Debian package (CPack): $(BUILD)/ausbau_<version>_<arch>.deb; install
# it with `apt-get install ./$(BUILD)/ausbau_*.deb`.
package: build
	cd $(call quote,$(BUILD)) && cpack -G DEB

# Every SCENES/*/scene.yaml, one OUT/<scene>/ each; parallel with -j N (give
# THREADS=1 then, so that the stages do not each take all cores). Prints a
# table of the verdicts; fails when any scene is not removable or failed.
batch: build
	@test -n $(call quote,$(SCENES)) || { echo "make batch: SCENES=folder (with */scene.yaml) is required" >&2; exit 2; }
	@$(MAKE) --no-print-directory -f pipelines/batch.mk $(call quote,SCENES=$(SCENES)) $(call quote,BIN=$(abspath $(BUILD)/bin)) \
	  $(call quote,OUT=$(or $(OUT),out/batch))

# A STEP assembly: ausbau-assembly writes a scene per part (OUT/scenes),
# then the batch above runs them all (pipelines/step.mk; DYNAMIC=name or
# path in the product tree for some parts only, DEFLECTION=mm).
step: build
	@test -n $(call quote,$(STEP)) || { echo "make step: STEP=assembly.step is required" >&2; exit 2; }
	@$(MAKE) --no-print-directory -f pipelines/step.mk $(call quote,STEP=$(STEP)) $(call quote,BIN=$(abspath $(BUILD)/bin)) \
	  $(call quote,OUT=$(or $(OUT),out/step))

# The same batch through Snakemake (pipelines/Snakefile; needs
# `scripts/install-deps.sh snakemake`): locally on CORES cores, or on a
# cluster with PROFILE=pipelines/slurm (run it on the login node). The
# pipeline variables below, given on the command line, become --config keys;
# SNAKEMAKE_ARGS adds options (-n, --forcerun plan, ...). Prints the table of
# make batch (OUT/verdicts.txt); fails when any scene is not removable or failed.
CORES ?= $(JOBS)
PROFILE ?=
SNAKEMAKE_ARGS ?=
SNAKEMAKE_OUT = $(or $(OUT),out/snakemake)
SNAKEMAKE_VARS := SEED TIME_LIMIT TAU_TIME_LIMIT VALIDITY RIGID_TOLERANCE PLANNER COLLISION THREADS BUDGET WITH_REPORT \
  VOXELIZE_FLAGS SPHERES_FLAGS LABEL_FLAGS DISTFIELD_FLAGS TAU_FLAGS PLAN_FLAGS SMOOTH_FLAGS VERDICT_FLAGS REPORT_FLAGS
# Snakemake runs in OUT (--directory), so its .snakemake/ state and the Slurm
# logs stay in OUT, never in the checkout; the paths it is given are made
# absolute from here first (a string join: abspath would split a name with
# a space into two paths).
from_here = $(if $(filter /%,$(1)),$(1),$(CURDIR)/$(1))
.PHONY: snakemake
snakemake: build
	@test -n $(call quote,$(SCENES)) || { echo "make snakemake: SCENES=folder (with */scene.yaml) is required" >&2; exit 2; }
	@command -v snakemake > /dev/null || { echo "make snakemake: snakemake is not installed (scripts/install-deps.sh snakemake)" >&2; exit 2; }
	@snakemake -s $(call quote,$(CURDIR)/pipelines/Snakefile) --directory $(call quote,$(call from_here,$(SNAKEMAKE_OUT))) \
	  $(if $(PROFILE),--profile $(call quote,$(call from_here,$(PROFILE))),--cores $(call quote,$(CORES))) $(SNAKEMAKE_ARGS) \
	  --config $(call quote,SCENES=$(call from_here,$(SCENES))) $(call quote,OUT=$(call from_here,$(SNAKEMAKE_OUT))) \
	  $(call quote,BIN=$(abspath $(BUILD)/bin)) \
	  $(foreach v,$(SNAKEMAKE_VARS),$(if $(filter command line,$(origin $(v))),$(call quote,$(v)=$($(v)))))
	@if [ -f $(call quote,$(SNAKEMAKE_OUT)/verdicts.txt) ] && ! grep -Eq '^batch: ([0-9]+) of \1 scenes removable' $(call quote,$(SNAKEMAKE_OUT)/verdicts.txt); then \
	  printf 'make snakemake: not every scene is removable (%s/verdicts.txt)\n' $(call quote,$(SNAKEMAKE_OUT)) >&2; exit 1; fi

# The C++ style (.clang-format, clang-format 14) on every tracked source but
# the few listed in scripts/format-pending.txt; fails on a file that differs.
# Part of .ci/run, before `make test`.
.PHONY: format-check
format-check:
	@scripts/install-deps.sh format || echo "format-check: clang-format-14 could not be installed" >&2
	@scripts/format-check.sh

test: build deps-browser deps-snakemake
	@cd $(call quote,$(BUILD)) && ctest --output-on-failure -j $(call quote,$(JOBS))

# The unit tests built with AddressSanitizer and UndefinedBehaviorSanitizer
# (-DAUSBAU_SANITIZE=ON: -O1 -g1, in $(SANITIZE_BUILD), apart from the
# release build); any finding fails the test. Builds only the target
# ausbau_unit_tests: the unit tests and the stages they run (no benchmarks,
# no end-to-end tests); flag_table (every executable's --help) is left to
# `make test`. Part of .ci/run; times in docs/testing.md.
SANITIZE_BUILD ?= build-sanitize
.PHONY: test-sanitize
test-sanitize: deps
	@cmake -S . -B $(call quote,$(SANITIZE_BUILD)) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DAUSBAU_SANITIZE=ON > /dev/null
	@cmake --build $(call quote,$(SANITIZE_BUILD)) -j $(call quote,$(JOBS)) --target ausbau_unit_tests
	@cd $(call quote,$(SANITIZE_BUILD)) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:abort_on_error=1 \
	  ctest -L unit -LE all-executables --output-on-failure -j $(call quote,$(JOBS))

# Chromium for the report's browser test; without it (no root, no apt) that
# test is skipped, so this never fails the test run.
.PHONY: deps-browser
# Snakemake (Debian's package) for the Snakefile's tests (ctest
# snakemake_batch, snakemake_slurm). .ci/run sets AUSBAU_REQUIRE_SNAKEMAKE=1,
# so that there a missing snakemake fails those tests instead of skipping them.
.PHONY: deps-snakemake
deps-snakemake:
	@scripts/install-deps.sh snakemake || echo "deps-snakemake: Snakemake could not be installed; the Snakefile's tests will be skipped" >&2

deps-browser:
	@scripts/install-deps.sh browser || echo "deps-browser: Chromium could not be installed; the browser test will be skipped" >&2

bench-deps:
	@scripts/install-deps.sh bench

bench-build: bench-deps
	@cmake -S . -B $(call quote,$(BUILD)) -DCMAKE_BUILD_TYPE=Release > /dev/null
	@cmake --build $(call quote,$(BUILD)) -j $(call quote,$(JOBS)) --target ausbau-bench || \
	  { echo "bench: ausbau-bench did not build (is OMPL installed? scripts/install-deps.sh bench)" >&2; exit 1; }

bench: bench-build
	@$(call quote,$(BUILD)/bin/ausbau-bench) --runs $(call quote,$(BENCH_RUNS)) --time-limit $(call quote,$(BENCH_TIME_LIMIT)) \
	  $(if $(BENCH_SCENES),--scenes $(call quote,$(BENCH_SCENES))) --output-dir $(call quote,$(BENCH_OUT)) $(BENCH_ARGS)
	@printf 'bench: %s/summary.md (printed above), results.csv (one row per run),\n' $(call quote,$(BENCH_OUT))
	@printf '       ompl-benchmark.log and ompl-benchmark-<scene>.log there (for ompl_benchmark_statistics.py)\n'

study: bench-build
	@$(call quote,$(BUILD)/bin/ausbau-bench) --study --runs $(call quote,$(STUDY_RUNS)) --time-limit $(call quote,$(STUDY_TIME_LIMIT)) \
	  --scenes $(call quote,$(STUDY_SCENES)) --output-dir $(call quote,$(STUDY_OUT)) $(STUDY_ARGS)
	@printf 'study: %s/study-summary.md (printed above), study-<scene>.csv and heat maps study-<scene>.svg\n' $(call quote,$(STUDY_OUT))

clean:
	rm -rf $(call quote,$(BUILD)) $(call quote,$(SANITIZE_BUILD)) out

# Ours against OMPL's RRT-Connect with its default range, side by side in one
# run (issue 29; docs/benchmarks.md "Planners against OMPL"): `ausbau-plan`
# as a user runs it (whole process, default flags) and CR-RRTC in process, on
# the OMPL.app scenes and the Parasol flange, and ours alone on the channel
# families (PLANNERS_CHANNELS seeds each of panel-channel, panel-zchannel and
# panel-keyhole, paths judged by the external set's oracle.py;
# scripts/planner-bench.sh). Writes summary.md (machine,
# tables, speed-ups), speedups.csv, results.csv and OMPL benchmark logs in
# PLANNERS_OUT, and checks the speed-ups against bench/planners/recorded.csv:
# it fails when one falls below half of the recorded one or a path fails the
# dense re-check. Up to PLANNERS_RUNS x 3 x PLANNERS_TIME_LIMIT s per scene
# (about 1-2 h on 2 cores). `make bench-planners-check` is the short version
# CI runs (.ci/run): alpha-1.5, Apartment and Home, 3 seeds, 30 s, against
# bench/planners/recorded-short.csv, about 2-3 min (not Easy: its whole
# process takes 0.05 s, mostly starting a process, so there the ratio would
# measure the machine's process start, not the planner). To record new figures, copy
# PLANNERS_OUT/speedups.csv over the recorded file and say why in the commit
# (PLANNERS_RECORDED= runs without the check).
PLANNERS_OUT ?= out/bench-planners
PLANNERS_RUNS ?= 3
PLANNERS_TIME_LIMIT ?= 60
PLANNERS_SCENES ?= alpha-1.0,alpha-1.2,alpha-1.5,Apartment,Easy,Home,Twistycool,cubicles,Abstract,bugtrap,$(abspath ../shared/benchmarks/parasol/flange-1.0/flange-1.0.yaml)
PLANNERS_CHANNELS ?= 1 2 3 4 5
PLANNERS_RECORDED ?= bench/planners/recorded.csv
PLANNERS_CHECK_OUT ?= out/bench-planners-check

.PHONY: bench-planners bench-planners-check
bench-planners: bench-build build
	@scripts/planner-bench.sh $(call quote,$(BUILD)/bin) $(call quote,$(PLANNERS_OUT)) $(call quote,$(PLANNERS_RUNS)) $(call quote,$(PLANNERS_TIME_LIMIT)) \
	  $(call quote,$(PLANNERS_SCENES)) $(call quote,$(PLANNERS_CHANNELS)) $(call quote,$(PLANNERS_RECORDED))

bench-planners-check: bench-build build
	@if [ ! -d ../shared/benchmarks/ompl ]; then \
	  echo "bench-planners-check: skipped: ../shared/benchmarks/ompl/ (the OMPL.app scenes) is not there" >&2; exit 0; fi; \
	$(call quote,$(BUILD)/bin/ausbau-bench) --planners ausbau-plan,cr-rrtc --ompl-ranges default --runs 3 --time-limit 30 \
	  --scenes alpha-1.5,Apartment,Home --output-dir $(call quote,$(PLANNERS_CHECK_OUT)) --recorded bench/planners/recorded-short.csv

# FARR against plain FCL (thesis 4.3: sample sets, detection rate, collision
# time, whole planning with the distance-field build) on alpha-1.2, alpha-1.5,
# Twistycool, the generated flange scenes and the Parasol flange; about
# 10-15 min with the defaults on 2 cores. Needs only the default build (no
# OMPL).
BENCH_FARR_OUT ?= out/bench-farr
BENCH_FARR_ARGS ?=

# The collision check of --validity collision (FCL's trees walked by
# collision/fcl_tree_walk.h) against FCL's own collide, on the poses CR-RRTC
# checks on the OMPL.app scenes: per-pose time, whole planning, and that the
# answers and paths are the same (bench/collision_bench.cpp). About 1 min.
BENCH_COLLISION_OUT ?= out/bench-collision
BENCH_COLLISION_ARGS ?=

# Path quality (docs/planning.md "Smoothing"): every generated family with a
# known path, PATHS_SEEDS seeds each, through the InIState pipeline; the
# smoothed path's translation and rotation against the known path's
# (scripts/path-quality-bench.sh). About 3-6 min on 2 cores.
PATHS_OUT ?= out/bench-paths
PATHS_SEEDS ?= 1 2 3 4
.PHONY: bench-paths
bench-paths: build
	@scripts/path-quality-bench.sh $(call quote,$(abspath $(BUILD)/bin)) $(call quote,$(PATHS_OUT)) $(call quote,$(PATHS_SEEDS))

# What each piece of the rigid planner buys (docs/benchmarks.md, issue 29):
# ausbau-plan once with its defaults and once per variant (Def-RRTC, the
# Gaussian, bridge and mixed samplers, FARR, planning at the certification's
# step) on the narrow-passage scenes (scripts/planner-ablation.sh). Up to
# ABLATION_RUNS x 7 x 6 x ABLATION_TIME_LIMIT s; about 30-40 min on 2 cores.
ABLATION_OUT ?= out/bench-ablation
ABLATION_RUNS ?= 3
ABLATION_TIME_LIMIT ?= 30
.PHONY: bench-ablation
bench-ablation: build
	@scripts/planner-ablation.sh $(call quote,$(abspath $(BUILD)/bin)) $(call quote,$(ABLATION_OUT)) \
	  $(call quote,$(ABLATION_RUNS)) $(call quote,$(ABLATION_TIME_LIMIT))

.PHONY: bench-farr
bench-farr: configure
	@cmake --build $(call quote,$(BUILD)) -j $(call quote,$(JOBS)) --target ausbau-farr-bench
	@$(call quote,$(BUILD)/bin/ausbau-farr-bench) --output-dir $(call quote,$(BENCH_FARR_OUT)) $(BENCH_FARR_ARGS)
	@printf 'bench-farr: %s/farr-summary.md (printed above), farr-results.csv\n' $(call quote,$(BENCH_FARR_OUT))

.PHONY: bench-collision
bench-collision: configure
	@cmake --build $(call quote,$(BUILD)) -j $(call quote,$(JOBS)) --target ausbau-collision-bench
	@$(call quote,$(BUILD)/bin/ausbau-collision-bench) --output-dir $(call quote,$(BENCH_COLLISION_OUT)) $(BENCH_COLLISION_ARGS)
	@printf 'bench-collision: %s/collision-summary.md (printed above)\n' $(call quote,$(BENCH_COLLISION_OUT))

# Thesis table 16 on the generated clip scenes clips-ds1 .. clips-ds5:
# shrink, IV, MLIV and Labeled-MLIV InIState planning (voxelize, label, tau,
# plan), each path checked against the generator's ground truth. Defaults: 5
# seeds, default triangle counts (thesis table 14), 20 s per planning part:
# about 13 min on 2 cores (labels take 10-30 s per ds1/ds2/ds5 scene); e.g.
# BENCH_INISTATE_ARGS="--families clips-ds3,clips-ds4 --seeds 1" for a smoke run.
BENCH_INISTATE_OUT ?= out/bench-inistate
BENCH_INISTATE_ARGS ?=

.PHONY: bench-inistate
bench-inistate: configure
	@cmake --build $(call quote,$(BUILD)) -j $(call quote,$(JOBS)) --target ausbau-inistate-bench
	@$(call quote,$(BUILD)/bin/ausbau-inistate-bench) --output-dir $(call quote,$(BENCH_INISTATE_OUT)) $(BENCH_INISTATE_ARGS)
	@printf 'bench-inistate: %s/inistate-summary.md (printed above), inistate-results.csv, inistate-scenes.csv\n' $(call quote,$(BENCH_INISTATE_OUT))

# The whole pipeline (pipelines/inistate.mk, default VALIDITY=auto) on every
# family, clips-ds* and panel-* (coarse, fine and the moulded twin, turned
# and metres out), seeds 1-3, and on the external set (box soup and
# moulded); each path.csv judged by the external oracle.py or the clip
# generator's ground truth. About 5 min on 2 cores without the moulded
# scenes; each moulded one takes up to the time limit (60 s) and more.
# Needs python3-numpy (apt-get install python3-numpy) for oracle.py.
BENCH_E2E_OUT ?= out/inistate-end-to-end
BENCH_E2E_ARGS ?=

.PHONY: bench-end-to-end
bench-end-to-end: build
	@$(call quote,$(BUILD)/bin/ausbau-inistate-bench) --end-to-end --output-dir $(call quote,$(BENCH_E2E_OUT)) $(BENCH_E2E_ARGS)
	@printf 'bench-end-to-end: %s/end-to-end-summary.md (printed above), end-to-end-results.csv\n' $(call quote,$(BENCH_E2E_OUT))

# The vehicle benchmark (issue 18, item 4; scripts/vehicle-bench.sh): a
# generated body shell of ~1.2M triangles with VEHICLE_PARTS fastened parts,
# every part's pipeline with a budget, a table in VEHICLE_OUT/vehicle-bench.md
# (verdict, time, peak memory per part, a projection for 800 parts). Seconds
# per part (docs/benchmarks.md); VEHICLE_RUN=10 runs the first ten only.
VEHICLE_OUT ?= out/bench-vehicle
VEHICLE_PARTS ?= 50
VEHICLE_RUN ?= $(VEHICLE_PARTS)
VEHICLE_BUDGET ?= 120
# VEHICLE_RUNNER=snakemake: the parts through pipelines/Snakefile on CORES
# cores (sharing S's cache) instead of one after the other through inistate.mk.
VEHICLE_RUNNER ?= make

.PHONY: bench-vehicle
bench-vehicle: build
	@RUNNER=$(call quote,$(VEHICLE_RUNNER)) CORES=$(call quote,$(CORES)) scripts/vehicle-bench.sh $(call quote,$(BUILD)/bin) $(call quote,$(VEHICLE_OUT)) $(call quote,$(VEHICLE_PARTS)) $(call quote,$(VEHICLE_RUN)) $(call quote,$(VEHICLE_BUDGET))

# The real-mesh benchmark (scripts/real-bench.sh): every bench/real/*/scene.yaml
# (public CAD and robot-assembly meshes: pegs in holes with tens of micrometres
# of clearance, caps on posts, a nut on a bolt, parts in m, cm, inch; see
# bench/real/README.md) through the InIState pipeline, one after the other,
# compared with its expected.yaml; prints a table (BENCH_REAL_OUT/real-bench.md).
# Fails only when a scene is wrongly removable. TIME_LIMIT=s is passed on.
BENCH_REAL_OUT ?= out/bench-real

.PHONY: bench-real
bench-real: build
	@scripts/real-bench.sh $(call quote,$(BUILD)/bin) $(call quote,$(BENCH_REAL_OUT)) bench/real

# The disassembly order on real meshes (scripts/order-bench.sh): assemblies
# made of the bench/real scenes' parts in their assembled poses
# (bench/real/tools/order_assemblies.py) through ausbau-order, each order
# compared with the one the geometry gives. Fails when one differs.
# PART_BUDGET=s (default 10) is passed on.
BENCH_ORDER_OUT ?= out/bench-order

.PHONY: bench-order
bench-order: build
	@scripts/order-bench.sh $(call quote,$(BUILD)/bin) $(call quote,$(BENCH_ORDER_OUT))

# The external benchmark set (scripts/external-bench.sh): its box-soup scenes
# and their moulded twins (D one welded solid) through the InIState pipeline,
# each path.csv judged by the set's own oracle.py. Fails only when a path
# the verdict called removable is refused by the oracle.
BENCH_EXTERNAL_OUT ?= out/bench-external

.PHONY: bench-external
bench-external: build
	@scripts/external-bench.sh $(call quote,$(BUILD)/bin) $(call quote,$(BENCH_EXTERNAL_OUT))

# libFuzzer harnesses of every file reader (docs/fuzzing.md): builds them with
# clang, ASan and UBSan in FUZZ_BUILD (needs clang and libFuzzer:
# `scripts/install-deps.sh fuzz`), runs each for FUZZ_SECONDS, then prints
# per harness the executions and the findings (crash files under
# FUZZ_BUILD/fuzz-out/<harness>/findings/). Fails when any harness has a
# finding. FUZZ_HARNESSES picks some, e.g. FUZZ_HARNESSES="scene mesh";
# FUZZ_RUNS=1000000 also stops each after that many executions.
FUZZ_SECONDS ?= 60
FUZZ_BUILD ?= build-fuzz
FUZZ_HARNESSES ?=
FUZZ_RUNS ?=

fuzz:
	@scripts/install-deps.sh fuzz
	@cmake -S . -B $(call quote,$(FUZZ_BUILD)) -DAUSBAU_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ > /dev/null
	@cmake --build $(call quote,$(FUZZ_BUILD)) -j $(call quote,$(JOBS)) --target ausbau_fuzzers
	@FUZZ_RUNS=$(call quote,$(FUZZ_RUNS)) fuzz/run.sh $(call quote,$(FUZZ_BUILD)) $(call quote,$(FUZZ_SECONDS)) $(FUZZ_HARNESSES)
