# The rigid planning pipeline for one scene: plan -> smooth -> report.
#   make -f pipelines/plan.mk SCENE=path/to/scene.yaml OUT=dir [SEED=1] [PLANNER=cr-rrtc]
# Each stage's executable is a variable, so a stage can be swapped:
#   make -f pipelines/plan.mk ... PLAN=/path/to/my-planner
# The stages themselves skip work whose output is up to date by provenance
# (inputs' content + options), so make always calls them.

BIN ?= build/bin
PLAN ?= $(BIN)/ausbau-plan
SMOOTH ?= $(BIN)/ausbau-smooth
REPORT ?= $(BIN)/ausbau-report
SCENE_GEN ?= $(BIN)/ausbau-scene-gen
SEED ?= 1
PLANNER ?= cr-rrtc
TIME_LIMIT ?= 60
# scene units: distance from S that plan and smooth keep where the path
# allows; -1: 0.5 mm in the scene's units (planning/clearance.h); 0: none.
CLEARANCE ?= -1
PLAN_FLAGS ?=
SMOOTH_FLAGS ?=

include $(dir $(lastword $(MAKEFILE_LIST)))scene-pipeline.mk
ifeq ($(OUT_LOCKED),yes)

.PHONY: all plan smooth report generate-demo-scene
.DELETE_ON_ERROR:

all: smooth report

plan:
	@mkdir -p $(OUT)
	$(PLAN) --scene $(SCENE) --planner $(PLANNER) --seed $(SEED) --time-limit $(TIME_LIMIT) --clearance $(CLEARANCE) \
	  -o $(RUN_PATH) --csv $(RUN_PATH_CSV) $(PLAN_FLAGS)

smooth: plan
	$(SMOOTH) --scene $(SCENE) --path $(RUN_PATH) --seed $(SEED) --clearance $(CLEARANCE) \
	  -o $(RUN_PATH_SMOOTH) --csv $(RUN_PATH_SMOOTH_CSV) $(SMOOTH_FLAGS)

report: smooth
	$(REPORT) --scene $(SCENE) --run-dir $(OUT) -o $(RUN_REPORT)

# Generated once: an existing scene (the demo's of an earlier run, or a
# user's) is kept, never replaced (ausbau-scene-gen refuses that too).
generate-demo-scene:
	@[ -f $(SCENE) ] || $(SCENE_GEN) --family rod-in-cage --seed $(SEED) -o $(dir $(SCENE)) > /dev/null

endif  # OUT_LOCKED (out-lock.mk)
