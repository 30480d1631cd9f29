# One pipeline at a time per OUT (included by scene-pipeline.mk, the head of
# inistate.mk and plan.mk). Two runs on one OUT interleave their stages: the first
# printed a verdict for files the second had replaced. So the whole run holds
# an exclusive lock on OUT/.ausbau-lock (flock, util-linux): make re-runs
# itself under the lock, and a second run on the same OUT stops at once with
#   pipeline: OUT <dir> is in use by pid N (...)
# and exit 2. A lock file that is a symbolic link is refused (exit 2): the
# pid would be written into the file it names. The including makefile puts its rules inside
#   ifeq ($(OUT_LOCKED),yes) ... endif
# so that the outer make (the one taking the lock) has only the rule below.
ifeq ($(AUSBAU_OUT_LOCK),$(abspath $(OUT)))
OUT_LOCKED := yes
else
OUT_LOCKED := no
.PHONY: out-lock $(MAKECMDGOALS)
# fd 9 stays open in the re-run make (exec keeps the pid, which is written
# into the lock file for the message) and in every stage it starts.
out-lock:
	@mkdir -p '$(OUT)'
	@$(call refuse_links,'$(OUT)/.ausbau-lock'); \
	exec 9>>'$(OUT)/.ausbau-lock'; \
	if ! flock -n 9; then \
	  echo "pipeline: OUT $(OUT) is in use by pid $$(cat '$(OUT)/.ausbau-lock' 2>/dev/null) (another pipeline is writing there; wait for it or choose another OUT)" >&2; \
	  exit 2; \
	fi; \
	echo $$$$ > '$(OUT)/.ausbau-lock'; \
	AUSBAU_OUT_LOCK='$(abspath $(OUT))' exec $(MAKE) -f $(firstword $(MAKEFILE_LIST)) $(MAKECMDGOALS)
$(filter-out out-lock,$(MAKECMDGOALS)): out-lock ; @:
endif
