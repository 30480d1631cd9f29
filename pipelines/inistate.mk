# The InIState pipeline for one scene (thesis ch. 5): is D removable, and how?
#
#   make -f pipelines/inistate.mk SCENE=path/to/scene.yaml OUT=dir [SEED=1] [TIME_LIMIT=60] ...
#
# With VALIDITY=rigid-exact (docs/rigid-exact.md) only
# plan -> smooth -> verdict [-> report] run: D's rigid solids are checked
# exactly, its fasteners are those that intersect S at the installed pose.
# The volume modes (VALIDITY=labeled-mliv, ...) run the whole chain. The
# default, auto, takes rigid-exact unless the scene needs the volume model.
#
#   voxelize ----------------------------\
#   medial-spheres -> pbd-label ----------> tau-estimate -> plan -> smooth -> verdict [-> report]
#   distfield-build ---------------------------------------/
#
# Outputs in OUT: the files of the manifest pipelines/run-files.txt (voxels.h5,
# spheres.h5, labels.h5, distfield-static.h5, distfield-dynamic.h5, tau.h5,
# tau-trace.csv, path.h5 (planned), path-smooth.h5 + path-smooth.csv
# (smoothed), path.csv (the final path: a copy of path-smooth.csv),
# profile.csv, verdict.json, report.html; RUN_PATH etc. below name them),
# times/<stage>.seconds (wall time of each stage in this run), and
# .ausbau-cache/ (the distance fields' cache, unless AUSBAU_CACHE_DIR names
# another). Nothing is written outside OUT.
#
# Caching: every stage skips work whose existing output has the same
# provenance (inputs' contents + options) and leaves that output untouched,
# so make always calls every stage; outputs are written atomically, so an
# interrupted run resumes where it stopped.
#
# Exit status: 0 when the verdict says removable. When no path is found,
# verdict.json is still written (status "not-removable", status_detail
# "not-removable (no path)" or "(budget)", the best partial path and the
# parts of S that block D at its end), path.csv and the
# smoothed files are removed, and make fails (the last step exits 3).
#
# Time budget: BUDGET=S (seconds) ends the run when S is used up (a positive
# number; above 1e9, about 30 years, it is taken as 1e9). The
# start of the run is taken once, when make reads this file, and every stage
# that can run long gets an absolute deadline (--deadline, seconds since the
# epoch) rather than a number of seconds: what the stages before it used is
# then counted without arithmetic in each recipe, and a stage started late
# gets only what is left. The shares of S (fractions of it after the start):
#   tau-estimate  0.40  (volume modes; no further planning round after it)
#   plan          0.75  (then the best partial path is written, path.h5
#                        stopped_by_budget; no path: smooth is skipped)
#   smooth        0.90  (stops early with the path shortened so far)
# and the rest for the verdict, which, where the budget ended the search,
# writes status_detail "not-removable (budget)", the partial path and the
# parts of S that block D at its end (blocked_by). voxelize, medial-spheres,
# pbd-label and distfield-build have no partial answer and are not cut (only
# the volume modes run them). The verdict records within_budget as before.
# A plan output cut short by the budget is never reused from the cache (the
# next run plans again); the deadline is not part of any cache key.
#
# Every stage's executable is a variable (VOXELIZE, MEDIAL_SPHERES, PBD_LABEL,
# DISTFIELD_BUILD, TAU_ESTIMATE, PLAN, SMOOTH, VERDICT, REPORT), so a stage
# can be swapped: make -f pipelines/inistate.mk ... PLAN=/path/to/my-planner

INISTATE_MK_DIR := $(dir $(lastword $(MAKEFILE_LIST)))

BIN ?= build/bin
VOXELIZE ?= $(BIN)/ausbau-voxelize
MEDIAL_SPHERES ?= $(BIN)/ausbau-medial-spheres
PBD_LABEL ?= $(BIN)/ausbau-pbd-label
DISTFIELD_BUILD ?= $(BIN)/ausbau-distfield-build
TAU_ESTIMATE ?= $(BIN)/ausbau-tau-estimate
PLAN ?= $(BIN)/ausbau-plan
SMOOTH ?= $(BIN)/ausbau-smooth
VERDICT ?= $(BIN)/ausbau-verdict
REPORT ?= $(BIN)/ausbau-report
TIMED ?= $(INISTATE_MK_DIR)../scripts/timed.sh

SEED ?= 1
TIME_LIMIT ?= 60          # ausbau-plan, seconds (sigma_1 and sigma_2 each)
TAU_TIME_LIMIT ?= 60      # ausbau-tau-estimate, seconds per planning round: a safety net (its --round-checks count the work)
VALIDITY ?= auto          # auto | rigid-exact | shrink | iv | mliv | labeled-mliv | labeled-mliv-unguarded (or collision: rigid only)
RIGID_TOLERANCE ?= 0.05   # mm (converted by the scene's units): how deep D's rigid part may touch into S
CLEARANCE ?= -1           # mm (converted by the scene's units): distance from S that plan and smooth keep where the path allows; -1: 0.5 mm; 0: none
PLANNER ?= auto           # ausbau-plan --planner (auto: EST for sigma_1, CR-RRTC otherwise)
COLLISION ?= farr         # farr (with the distance fields) | fcl (no distfield-build)
THREADS ?= 0              # --threads of the parallel stages; 0 = all cores
BUDGET ?=                 # seconds the whole run may take: the work stops when they are used up (see "Time budget" above)
WITH_REPORT ?= 1          # 0: no report.html
VOXELIZE_FLAGS ?=
SPHERES_FLAGS ?=
LABEL_FLAGS ?=
DISTFIELD_FLAGS ?=
TAU_FLAGS ?=
PLAN_FLAGS ?=
SMOOTH_FLAGS ?=
VERDICT_FLAGS ?=
REPORT_FLAGS ?=

include $(dir $(lastword $(MAKEFILE_LIST)))scene-pipeline.mk
ifeq ($(OUT_LOCKED),yes)

# Make's `?=` keeps the spaces before a comment: strip them.
SEED := $(strip $(SEED))
TIME_LIMIT := $(strip $(TIME_LIMIT))
TAU_TIME_LIMIT := $(strip $(TAU_TIME_LIMIT))
override VALIDITY := $(strip $(VALIDITY))
override BUDGET := $(strip $(BUDGET))
ifneq ($(BUDGET),)
$(call require_safe,BUDGET)
ifneq ($(shell awk -v b='$(BUDGET)' 'BEGIN { print (b ~ /^[0-9]*\.?[0-9]+([eE][+]?[0-9]+)?$$/ && b + 0 > 0) ? "ok" : "bad" }'),ok)
$(error BUDGET=$(BUDGET): must be a positive number of seconds)
endif
# More than 1e9 s (30 years) is as good as none: taken as 1e9, for the
# deadlines and the verdict's record alike (BUDGET=1e308 works; 1e309 and
# more, which are no double, too).
# (override: BUDGET is mostly given on the command line, whose value a plain
# assignment would not change.)
override BUDGET := $(shell awk -v b='$(BUDGET)' 'BEGIN { if (b + 0 > 1e9) print "1e9"; else print b }')
BUDGET_START := $(shell date +%s.%N)
budget_deadline = $(shell awk -v s=$(BUDGET_START) -v b=$(BUDGET) -v f=$(1) 'BEGIN { printf "%.3f", s + f * b }')
TAU_DEADLINE := $(call budget_deadline,0.40)
PLAN_DEADLINE := $(call budget_deadline,0.75)
SMOOTH_DEADLINE := $(call budget_deadline,0.90)
endif
# auto: rigid-exact, unless D intersects S at the installed pose where the
# exact check cannot measure the depth (then labeled-mliv; ausbau-plan
# --choose-validity). A plan stage that cannot answer gets rigid-exact.
ifeq ($(VALIDITY),auto)
override VALIDITY := $(or $(filter rigid-exact labeled-mliv,$(shell $(PLAN) --scene $(SCENE) --choose-validity --rigid-tolerance $(strip $(RIGID_TOLERANCE)) --log-level error 2>/dev/null)),rigid-exact)
$(info inistate: VALIDITY=auto: $(VALIDITY))
endif
RIGID_TOLERANCE := $(strip $(RIGID_TOLERANCE))
CLEARANCE := $(strip $(CLEARANCE))
PLANNER := $(strip $(PLANNER))
COLLISION := $(strip $(COLLISION))
THREADS := $(strip $(THREADS))
WITH_REPORT := $(strip $(WITH_REPORT))

TIMES := $(OUT)/times
# The stages' cache of distance fields (collision/distance_field.h) would go
# beside the scene (<scene folder>/.ausbau-cache): the pipeline writes inside
# OUT only, so it goes there, unless the user chose one (a shared cache).
export AUSBAU_CACHE_DIR ?= $(abspath $(OUT))/.ausbau-cache
# Every stage of the run reads S's meshes; a mesh file of 1 MiB or more is
# parsed once and kept there too, keyed by its bytes (scene/mesh_io.h
# MeshCacheDir): a car body of 1.2M triangles loads in a few tenths of a
# second instead of seconds per stage. batch.mk and the Snakefile point every
# scene of an assembly at one folder, so S is parsed once per assembly.
export AUSBAU_MESH_CACHE ?= $(AUSBAU_CACHE_DIR)
VOLUME_MODE := $(filter-out collision rigid-exact,$(VALIDITY))
# rigid-exact (docs/rigid-exact.md): exact shell depths, no voxels,
# labels, tau or distance fields.
EXACT_MODE := $(filter rigid-exact,$(VALIDITY))

# Stages that only sigma_1's volume validity needs, and FARR's fields.
GEOMETRY_STAGES := $(if $(VOLUME_MODE),voxelize medial-spheres pbd-label) $(if $(EXACT_MODE),,$(if $(filter farr,$(COLLISION)),distfield-build))
VOLUME_INPUTS := --voxels $(RUN_VOXELS) --labels $(RUN_LABELS)
PLAN_VOLUME := $(if $(VOLUME_MODE),--validity $(VALIDITY) --tau-file $(RUN_TAU) $(VOLUME_INPUTS))$(if $(EXACT_MODE),--validity rigid-exact) --rigid-tolerance $(RIGID_TOLERANCE)
COMMA := ,
PLAN_COLLISION := $(if $(EXACT_MODE),,--collision $(COLLISION) $(if $(filter farr,$(COLLISION)),--distfield $(RUN_DISTFIELD_STATIC)$(COMMA)$(RUN_DISTFIELD_DYNAMIC)))

.PHONY: all start voxelize medial-spheres pbd-label distfield-build tau-estimate plan smooth verdict report
.DELETE_ON_ERROR:
.DEFAULT_GOAL := all

all: verdict $(if $(filter 1,$(WITH_REPORT)),report)
	@grep -Eq '"removable"[[:space:]]*:[[:space:]]*true' $(RUN_VERDICT) || \
	  { echo "inistate: $(SCENE): not removable (see $(RUN_VERDICT))" >&2; exit 3; }

# This run's timings only (stale ones would be summed by the verdict), and
# no verdict of an earlier run when this one fails before its verdict. The
# pipeline's own paths that recipes (not stages) write or delete must not be
# symbolic links: they would lead the rm and the writes outside OUT.
start:
	@$(call refuse_links,$(TIMES) $(RUN_PATH_CSV_TMP) $(RUN_PATH_CSV) $(OUT)/.ausbau-cache)
	@mkdir -p $(TIMES)
	@rm -f $(TIMES)/*.seconds $(TIMES)/no-path $(RUN_VERDICT)

voxelize: start
	$(TIMED) voxelize $(TIMES) $(VOXELIZE) --scene $(SCENE) --threads $(THREADS) -o $(RUN_VOXELS) $(VOXELIZE_FLAGS)

medial-spheres: start
	$(TIMED) medial-spheres $(TIMES) $(MEDIAL_SPHERES) --scene $(SCENE) --threads $(THREADS) \
	  -o $(RUN_SPHERES) $(SPHERES_FLAGS)

pbd-label: medial-spheres
	$(TIMED) pbd-label $(TIMES) $(PBD_LABEL) --scene $(SCENE) --spheres $(RUN_SPHERES) --threads $(THREADS) \
	  --rigid-tolerance $(RIGID_TOLERANCE) -o $(RUN_LABELS) $(LABEL_FLAGS)

distfield-build: start
	$(TIMED) distfield-build $(TIMES) $(DISTFIELD_BUILD) --scene $(SCENE) --threads $(THREADS) \
	  --output-dir $(OUT) $(DISTFIELD_FLAGS) > /dev/null

# Exit 3 (no round found sigma_1) still writes tau.h5 with the last tau
# tried; the planner gets its chance with it.
TAU_CMD = $(TAU_ESTIMATE) --scene $(SCENE) --validity $(VALIDITY) $(VOLUME_INPUTS) --rigid-tolerance $(RIGID_TOLERANCE) --seed $(SEED) \
  --time-limit $(TAU_TIME_LIMIT) --threads $(THREADS) $(if $(BUDGET),--deadline $(TAU_DEADLINE)) \
  -o $(RUN_TAU) --csv $(RUN_TAU_TRACE) $(TAU_FLAGS)
tau-estimate: start $(if $(VOLUME_MODE),voxelize pbd-label)
ifneq ($(VOLUME_MODE),)
	@echo '$(TAU_CMD)'; rc=0; $(TIMED) tau-estimate $(TIMES) $(TAU_CMD) || rc=$$?; \
	if [ $$rc -eq 3 ]; then echo "inistate: tau-estimate found no sigma_1; planning with its last tau" >&2; \
	elif [ $$rc -ne 0 ]; then exit $$rc; fi
else
	@rm -f $(RUN_TAU) $(RUN_TAU_TRACE)
endif

# Exit 3 (no path within the budget) writes path.h5 with success = 0: then
# the smoothed files and path.csv are removed, smoothing is skipped
# (times/no-path marks it) and the verdict reads path.h5.
PLAN_CMD = $(PLAN) --scene $(SCENE) --planner $(PLANNER) --seed $(SEED) --time-limit $(TIME_LIMIT) \
  --threads $(THREADS) --clearance $(CLEARANCE) $(PLAN_COLLISION) $(PLAN_VOLUME) $(if $(BUDGET),--deadline $(PLAN_DEADLINE)) \
  -o $(RUN_PATH) $(PLAN_FLAGS)
plan: tau-estimate $(filter distfield-build,$(GEOMETRY_STAGES))
	@echo '$(PLAN_CMD)'; rc=0; $(TIMED) plan $(TIMES) $(PLAN_CMD) || rc=$$?; \
	if [ $$rc -eq 3 ]; then \
	  echo "inistate: no path found; the verdict will say not removable" >&2; touch $(TIMES)/no-path; \
	  rm -f $(RUN_PATH_CSV) $(RUN_PATH_SMOOTH) $(RUN_PATH_SMOOTH_CSV) $(RUN_PROFILE); \
	elif [ $$rc -ne 0 ]; then exit $$rc; fi

SMOOTH_CMD = $(SMOOTH) --scene $(SCENE) --path $(RUN_PATH) --seed $(SEED) $(if $(VOLUME_MODE),$(VOLUME_INPUTS)) \
  --rigid-tolerance $(RIGID_TOLERANCE) --clearance $(CLEARANCE) $(if $(BUDGET),--deadline $(SMOOTH_DEADLINE)) --profile $(RUN_PROFILE) \
  -o $(RUN_PATH_SMOOTH) --csv $(RUN_PATH_SMOOTH_CSV) $(SMOOTH_FLAGS)
# (mv -T: a link put at path.csv during the run, to a folder too, is
# replaced, never moved into; `start` refused one before.)
smooth: plan
	@if [ -f $(TIMES)/no-path ]; then echo "inistate: smooth skipped (no path)"; exit 0; fi; \
	echo '$(SMOOTH_CMD)'; $(TIMED) smooth $(TIMES) $(SMOOTH_CMD) && \
	rm -f $(RUN_PATH_CSV_TMP) && cp $(RUN_PATH_SMOOTH_CSV) $(RUN_PATH_CSV_TMP) && mv -fT $(RUN_PATH_CSV_TMP) $(RUN_PATH_CSV)

# Exit 3 (not removable) still writes verdict.json; `all` fails afterwards,
# so that the report is written for a failed scene too.
VERDICT_ARGS = --scene $(SCENE) $(if $(VOLUME_MODE),--tau-file $(RUN_TAU)) --times $(TIMES) \
  $(if $(BUDGET),--budget $(BUDGET)) --rigid-tolerance $(RIGID_TOLERANCE) -o $(RUN_VERDICT) $(VERDICT_FLAGS)
verdict: smooth
	@if [ -f $(TIMES)/no-path ]; then set -- --path $(RUN_PATH); \
	else set -- --path $(RUN_PATH_SMOOTH) --csv-name $(RUN_PATH_CSV); fi; \
	echo "$(VERDICT) $$* $(VERDICT_ARGS)"; rc=0; $(VERDICT) "$$@" $(VERDICT_ARGS) || rc=$$?; \
	if [ $$rc -ne 0 ] && [ $$rc -ne 3 ]; then exit $$rc; fi

report: verdict
	$(REPORT) --scene $(SCENE) --run-dir $(OUT) -o $(RUN_REPORT) $(REPORT_FLAGS)

endif  # OUT_LOCKED (out-lock.mk)
