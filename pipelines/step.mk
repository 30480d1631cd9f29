# A STEP assembly, one command: a scene per part (ausbau-assembly: the
# product tree read and tessellated once), then the InIState pipeline on
# every part (pipelines/batch.mk) and a table of the verdicts.
#
#   make -f pipelines/step.mk STEP=assembly.step OUT=dir [DYNAMIC=name-or-path]
#        [DEFLECTION=mm] [-j N] [any inistate.mk variable]
#
# Writes OUT/scenes/<part>/scene.yaml, OUT/scenes/assembly.json (the tree,
# paths, placements, units, tessellation), OUT/scenes/<stem>.tessellated.obj,
# and per part OUT/<part>/ (verdict.json, path.csv, pipeline.log). Like
# batch.mk it exits 1 when any part is not removable (in an assembly most
# parts are held by others: read the table).

STEP_MK_DIR := $(dir $(lastword $(MAKEFILE_LIST)))
BIN ?= build/bin

include $(STEP_MK_DIR)safe-names.mk
$(call require_given,STEP,assembly.step)
$(call require_given,OUT,output/folder)
$(call require_safe,BIN)
ifdef DYNAMIC
$(call require_safe,DYNAMIC)
endif
ifdef DEFLECTION
$(call require_safe,DEFLECTION)
endif

.PHONY: all scenes
.DEFAULT_GOAL := all

# ausbau-assembly writes atomically and only what changed is re-planned
# (every stage caches by content).
scenes:
	@mkdir -p $(OUT)
	$(BIN)/ausbau-assembly --assembly $(STEP) -o $(OUT)/scenes $(if $(DYNAMIC),--dynamic $(DYNAMIC)) \
	  $(if $(DEFLECTION),--deflection $(DEFLECTION)) > /dev/null

all: scenes
	@$(MAKE) --no-print-directory -f $(STEP_MK_DIR)batch.mk SCENES=$(OUT)/scenes OUT=$(OUT) BIN=$(abspath $(BIN))
