# Ausbau: the two commands a new user needs.
#   make demo   installs what is missing (Debian packages), builds, and plans a
#               disassembly path on a generated scene
#   make test   the same set-up, then the whole test suite
# Everything builds into build/; stage executables land in build/bin/.

BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_OUT ?= out/demo
SEED ?= 1

.PHONY: all deps configure build demo test clean
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

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) out
