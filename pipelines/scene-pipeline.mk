# The head of a pipeline for one scene (inistate.mk, plan.mk): SCENE and OUT
# given and safe to reach a shell (safe-names.mk), and one run at a time per
# OUT (out-lock.mk: the including makefile puts its rules inside
# `ifeq ($(OUT_LOCKED),yes) ... endif`).
SCENE_PIPELINE_DIR := $(dir $(lastword $(MAKEFILE_LIST)))
include $(SCENE_PIPELINE_DIR)safe-names.mk
$(call require_given,SCENE,path/to/scene.yaml)
$(call require_given,OUT,output/folder)
include $(SCENE_PIPELINE_DIR)out-lock.mk

# The run's files, named by the manifest run-files.txt (the Snakefile, the
# stages, the report and the goldens read the same file): one variable per
# line of it, RUN_<KEY> (upper case, - as _) = $(OUT)/<file>: RUN_PATH is
# $(OUT)/path.h5, RUN_PATH_SMOOTH_CSV $(OUT)/path-smooth.csv.
RUN_FILES_TABLE := $(shell awk '!/^[[:space:]]*(\#|$$)/ { name = toupper($$1); gsub("-", "_", name); print name "=" $$2 }' '$(SCENE_PIPELINE_DIR)run-files.txt')
$(foreach entry,$(RUN_FILES_TABLE),$(eval RUN_$(word 1,$(subst =, ,$(entry))) := $(OUT)/$(word 2,$(subst =, ,$(entry)))))
# The temporary that path.csv is written through (renamed onto it).
RUN_PATH_CSV_TMP := $(OUT)/.$(notdir $(RUN_PATH_CSV)).tmp
