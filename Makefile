# f16mmae — the README's two commands: `make demo` and `make test`.
# Both set up what they need (Debian build packages, a .venv in the repo), build, and run.
# Idempotent: a second run only rebuilds what changed.

SHELL       := /bin/bash
PYTHON      ?= python3
VENV        := .venv
PY          := $(VENV)/bin/python
PIP         := $(PY) -m pip
APT_PKGS    := g++ libeigen3-dev libgtest-dev googletest libglib2.0-dev libsodium-dev clang libclang-rt-14-dev
BUILD_REQS  := "scikit-build-core>=0.10" "pybind11>=2.13" "lcm>=1.5,<1.6" "jsbsim>=1.3,<1.4" cmake ninja
SITE         = $(shell $(PY) -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
JOBS        ?= 2

.PHONY: demo test setup apt venv build ctest pytest fuzz-check fuzz bench clean help

help:
	@echo "make demo   set up, build, run the main job on its embedded default"
	@echo "make test   set up, build, run every test (ctest, pytest, fuzz corpora + $(FUZZ_SECONDS) s per fuzz target)"
	@echo "make fuzz   run every fuzz target for FUZZ_LONG_SECONDS (default $(FUZZ_LONG_SECONDS)) s"
	@echo "make build  (re)build the Python package and its C++ extension"
	@echo "make bench  print the estimator benchmark"

demo: build
	$(VENV)/bin/f16mmae campaign single --runs 30 --out results/demo
	@echo "demo report: $(CURDIR)/results/demo/report.html"

test: build ctest pytest fuzz-check

setup: apt venv

# Debian packages: installed only when one is missing (needs root, as on this machine kind).
apt:
	@missing=$$(for p in $(APT_PKGS); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:" $$missing; \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi

$(VENV)/.stamp: pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip
	$(PIP) install -q $(BUILD_REQS)
	@touch $@

venv: $(VENV)/.stamp

# Editable install with a kept build directory: incremental C++ rebuilds, Python from source;
# the extras bring pytest, filterpy (bench) and distributed (Dask campaigns, tested).
# flock serialises concurrent builds of the same tree.
build: setup
	@mkdir -p build
	flock build/.lock $(PIP) install -q --no-build-isolation -Cbuild-dir=build/py -e ".[test,bench,dask]"

build/cpp/CMakeCache.txt: | setup
	$(VENV)/bin/cmake -S . -B build/cpp -G Ninja -DCMAKE_BUILD_TYPE=Release \
	  -DCMAKE_PREFIX_PATH="$(SITE)" -DF16MMAE_BUILD_PYTHON=OFF

ctest: build/cpp/CMakeCache.txt
	flock build/.lock-cpp $(VENV)/bin/cmake --build build/cpp -j $(JOBS)
	$(VENV)/bin/ctest --test-dir build/cpp --output-on-failure -j $(JOBS)

pytest: build
	$(PY) -m pytest -q

# libFuzzer targets (tests/fuzz) in their own clang + AddressSanitizer build. fuzz-check
# replays the committed corpora and fuzzes each of the 5 targets FUZZ_SECONDS (5 x 15 s = 75 s
# in `make test`); `make fuzz` runs each FUZZ_LONG_SECONDS. New inputs stay in build/fuzz.
FUZZ_SECONDS      ?= 15
FUZZ_LONG_SECONDS ?= 600
FUZZ_CMAKE = $(VENV)/bin/cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_PREFIX_PATH="$(SITE)" \
	  -DF16MMAE_BUILD_PYTHON=OFF -DF16MMAE_BUILD_TESTS=OFF -DF16MMAE_BUILD_FUZZERS=ON

fuzz-check: setup
	@mkdir -p build
	$(FUZZ_CMAKE) -DF16MMAE_FUZZ_SECONDS=$(FUZZ_SECONDS) >/dev/null
	flock build/.lock-fuzz $(VENV)/bin/cmake --build build/fuzz --target fuzzers -j $(JOBS)
	$(VENV)/bin/ctest --test-dir build/fuzz --output-on-failure

fuzz: setup
	@mkdir -p build
	$(FUZZ_CMAKE) -DF16MMAE_FUZZ_SECONDS=$(FUZZ_LONG_SECONDS) >/dev/null
	flock build/.lock-fuzz $(VENV)/bin/cmake --build build/fuzz --target fuzzers -j $(JOBS)
	$(VENV)/bin/ctest --test-dir build/fuzz --output-on-failure

bench: build
	$(VENV)/bin/f16mmae bench estimator

clean:
	rm -rf build
