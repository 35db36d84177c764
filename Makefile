# needlesim: the two commands of the README.
#   make run   installs what is missing, builds, runs the built-in default scenario
#   make test  installs what is missing, builds, runs the whole test suite (CTest)
PRESET ?= release
BIN := build/$(PRESET)/apps/needlesim/needlesim

.PHONY: run test build bootstrap configure clean bench

bootstrap:
	@bash scripts/bootstrap.sh

configure: bootstrap
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build --preset $(PRESET)

run: build
	@$(BIN) run

test: build
	@ctest --preset $(PRESET)

bench: build
	@for b in build/$(PRESET)/bench/bench_*; do $$b; done

clean:
	rm -rf build
