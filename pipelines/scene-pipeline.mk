# The head of a pipeline for one scene (inistate.mk, plan.mk): SCENE and OUT
# given and safe to reach a shell (safe-names.mk), and one run at a time per
# OUT (out-lock.mk: the including makefile puts its rules inside
# `ifeq ($(OUT_LOCKED),yes) ... endif`).
SCENE_PIPELINE_DIR := $(dir $(lastword $(MAKEFILE_LIST)))
include $(SCENE_PIPELINE_DIR)safe-names.mk
$(call require_given,SCENE,path/to/scene.yaml)
$(call require_given,OUT,output/folder)
include $(SCENE_PIPELINE_DIR)out-lock.mk
