# The InIState pipeline (pipelines/inistate.mk) on every SCENES/*/scene.yaml,
# one sub-folder of OUT per scene, in parallel with make -j; then a table of
# the verdicts. Fails when any scene is not removable or its pipeline failed.
#
#   make -f pipelines/batch.mk SCENES=dir OUT=dir [-j N] [any inistate.mk variable]
#
# Each scene's output goes to OUT/<scene>/pipeline.log (not interleaved on
# the terminal) and its exit status to OUT/<scene>/pipeline.exit.

BATCH_MK_DIR := $(dir $(lastword $(MAKEFILE_LIST)))

include $(BATCH_MK_DIR)safe-names.mk
$(call require_given,SCENES,folder/with/one/sub-folder/per/scene)
$(call require_given,OUT,output/folder)
SCENE_FILES := $(sort $(wildcard $(SCENES)/*/scene.yaml))
NAMES := $(patsubst $(SCENES)/%/scene.yaml,%,$(SCENE_FILES))
ifeq ($(strip $(NAMES)),)
$(error no $(SCENES)/*/scene.yaml found)
endif
# Folder names name the outputs and reach the recipes below. (A name with a
# space arrives split in two, the second part ending in /scene.yaml.)
$(foreach name,$(NAMES),$(if $(and $(call safe_var,name),$(if $(findstring /,$(name)),,yes)),,\
  $(error SCENES=$(SCENES): a scene folder name has a space or characters that would reach a shell (near '$(name)'); use letters, digits and _.+@-)))

# One cache for every scene (inistate.mk): the parts of an assembly share
# S's file, which is then parsed once, not once per part and stage.
export AUSBAU_CACHE_DIR ?= $(abspath $(OUT))/.ausbau-cache
export AUSBAU_MESH_CACHE ?= $(AUSBAU_CACHE_DIR)

.PHONY: all $(addprefix scene-,$(NAMES))
.DEFAULT_GOAL := all

all: $(addprefix scene-,$(NAMES))
	@$(BATCH_MK_DIR)../scripts/verdict-table.sh $(OUT) $(NAMES)

# The sub-make's failure is recorded, not propagated: the table decides.
# The scene's folder, its log and its exit file are written by the shell
# (a redirection follows a link): a link there is refused, not followed.
$(addprefix scene-,$(NAMES)): scene-%:
	@$(call refuse_links,$(OUT)/$* $(OUT)/$*/pipeline.log $(OUT)/$*/pipeline.exit $(OUT)/.ausbau-cache)
	@mkdir -p $(OUT)/$*
	@echo "batch: $* ..."
	@rc=0; $(MAKE) --no-print-directory -f $(BATCH_MK_DIR)inistate.mk SCENE=$(SCENES)/$*/scene.yaml OUT=$(OUT)/$* \
	  > $(OUT)/$*/pipeline.log 2>&1 || rc=$$?; echo $$rc > $(OUT)/$*/pipeline.exit; \
	echo "batch: $* done (exit $$rc)"
