# Ausbau: the two commands a new user needs.
#   make demo   installs what is missing (Debian packages), builds, and plans a
#               disassembly path on a generated scene
#   make test   the same set-up, then the whole test suite
# Everything builds into build/; stage executables land in build/bin/.

BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= out/demo
SEED ?= 1

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

.PHONY: all deps configure build demo test clean bench-deps bench-build bench study
.DELETE_ON_ERROR:

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > /dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	@$(MAKE) --no-print-directory -f pipelines/plan.mk \
	  SCENE=$(DEMO_OUT)/scene/scene.yaml OUT=$(DEMO_OUT) BIN=$(BUILD)/bin SEED=$(SEED) generate-demo-scene all
	@echo "demo: path written to $(DEMO_OUT)/path.csv (smoothed: $(DEMO_OUT)/path-smooth.csv)"
	@echo "demo: report: $(DEMO_OUT)/report.html (one self-contained HTML file: open it in a browser)"

test: build deps-browser
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Chromium for the report's browser test; without it (no root, no apt) that
# test is skipped, so this never fails the test run.
.PHONY: deps-browser
deps-browser:
	@scripts/install-deps.sh browser || echo "deps-browser: Chromium could not be installed; the browser test will be skipped" >&2

bench-deps:
	@scripts/install-deps.sh bench

bench-build: bench-deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > /dev/null
	@cmake --build $(BUILD) -j $(JOBS) --target ausbau-bench || \
	  { echo "bench: ausbau-bench did not build (is OMPL installed? scripts/install-deps.sh bench)" >&2; exit 1; }

bench: bench-build
	@$(BUILD)/bin/ausbau-bench --runs $(BENCH_RUNS) --time-limit $(BENCH_TIME_LIMIT) \
	  $(if $(BENCH_SCENES),--scenes $(BENCH_SCENES)) --output-dir $(BENCH_OUT) $(BENCH_ARGS)
	@echo "bench: $(BENCH_OUT)/summary.md (printed above), $(BENCH_OUT)/results.csv (one row per run),"
	@echo "       $(BENCH_OUT)/ompl-benchmark.log and ompl-benchmark-<scene>.log (for ompl_benchmark_statistics.py)"

study: bench-build
	@$(BUILD)/bin/ausbau-bench --study --runs $(STUDY_RUNS) --time-limit $(STUDY_TIME_LIMIT) \
	  --scenes $(STUDY_SCENES) --output-dir $(STUDY_OUT) $(STUDY_ARGS)
	@echo "study: $(STUDY_OUT)/study-summary.md (printed above), study-<scene>.csv and heat maps study-<scene>.svg"

clean:
	rm -rf $(BUILD) out

# FARR against plain FCL (thesis 4.3: sample sets, detection rate, collision
# time, whole planning with the distance-field build) on alpha-1.2, alpha-1.5,
# Twistycool, the generated flange scenes and the Parasol flange; about
# 10-15 min with the defaults on 2 cores. Needs only the default build (no
# OMPL).
BENCH_FARR_OUT ?= out/bench-farr
BENCH_FARR_ARGS ?=

.PHONY: bench-farr
bench-farr: configure
	@cmake --build $(BUILD) -j $(JOBS) --target ausbau-farr-bench
	@$(BUILD)/bin/ausbau-farr-bench --output-dir $(BENCH_FARR_OUT) $(BENCH_FARR_ARGS)
	@echo "bench-farr: $(BENCH_FARR_OUT)/farr-summary.md (printed above), $(BENCH_FARR_OUT)/farr-results.csv"
