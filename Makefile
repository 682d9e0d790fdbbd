# granboltz: the two commands a new user needs are `make reproduce` and `make test`.
SHELL := /bin/bash
# Debian's Python first: pyenv's python3 does not see python3-h5py and friends.
export PATH := /usr/bin:$(PATH)
BUILD ?= build
JOBS ?= 2
PROFILE ?= config/quick.yaml

.PHONY: all deps deps-browser build python test test-cpp test-python test-sanitize test-slurm docs fuzz reproduce check-tables check-coverage format paper bench bench-counters bench-peer sanitize clean

all: build

deps:
	@bash scripts/install-deps.sh

## make deps-browser: the dependencies plus Chromium (large), for the browser test of the report
deps-browser:
	@bash scripts/install-deps.sh --with-browser

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

## make python: install the Python package granboltz (src/python/granboltz) for Debian's
## /usr/bin/python3, editable (this source tree) and offline (Debian's pip and setuptools, no
## PyPI); skipped when this tree's package is already the one imported. The extension
## granboltz._core is built by `make build` into $(BUILD)/python/granboltz/ and linked into
## src/python/granboltz/ (gitignored); this target links it again for a BUILD of its own.
PYTHON := /usr/bin/python3
python:
	@for so in $(BUILD)/python/granboltz/_core*.so; do \
	  if [ -e "$$so" ]; then ln -sfn "$(abspath $(BUILD))/python/granboltz/$$(basename "$$so")" src/python/granboltz/; fi; \
	done
	@if cd / && $(PYTHON) -c "import granboltz, os, sys; sys.exit(os.path.realpath(granboltz.__path__[0]) != os.path.realpath('$(CURDIR)/src/python/granboltz'))" 2>/dev/null; then \
	  echo "python: granboltz from $(CURDIR)/src/python is installed"; \
	else \
	  $(PYTHON) -m pip install --user --break-system-packages --no-build-isolation --no-deps --quiet --root-user-action=ignore -e "$(CURDIR)"; \
	fi

## make test: build, then the C++ suite (ctest) and the Python suite (pytest)
test: deps build python test-cpp test-python

test-cpp:
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

## The browser test of the HTML report runs where Chromium is installed (make deps-browser) and
## is skipped, with the reason printed, where it is not.
CHROMIUM ?= $(shell command -v chromium || command -v chromium-browser)
test-python:
	@if [ -n "$(CHROMIUM)" ]; then \
	  echo "test-python: the browser test of the report runs in $$($(CHROMIUM) --version 2>/dev/null)"; \
	else \
	  echo "test-python: Chromium not installed: the browser test of the report is SKIPPED (make deps-browser)"; \
	fi
	CHROMIUM="$(CHROMIUM)" /usr/bin/python3 -m pytest -q -rs tests/python

## make docs: the documentation site (Sphinx, furo, myst-parser; Debian packages) into
## build/docs/html/ (open build/docs/html/index.html); warnings are errors. It builds the
## simulator first: the API pages of granboltz.lib.inprocess need the extension granboltz._core.
DOCS_OUT ?= build/docs
docs: deps build
	/usr/bin/python3 -m sphinx -b html -W --keep-going -q -d $(DOCS_OUT)/doctrees docs $(DOCS_OUT)/html
	@echo "docs: $(DOCS_OUT)/html/index.html"

## make test-sanitize: the C++ suite built with AddressSanitizer + UndefinedBehaviorSanitizer
## (build-asan; every finding, leaks included, fails the test), without the tests labelled slow
## or timing (wall times compared with the constants of the optimised build)
SANITIZE_BUILD ?= build-asan
test-sanitize: deps
	cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGRANBOLTZ_SANITIZE=ON \
	  -DGRANBOLTZ_BENCH=OFF
	cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	cd $(SANITIZE_BUILD) && ctest --output-on-failure -j $(JOBS) -LE "slow|timing"

## make test-slurm: the SLURM profile against a one-node SLURM started here (munge, slurmctld,
## slurmd; installs slurm-wlm and munge): GRW05 tail shards, merges and a table through the
## profile, one job preempted and resumed, results identical to the local run (exit 77: this
## machine cannot host SLURM)
test-slurm: deps build
	bash scripts/test-slurm.sh

## make fuzz MINUTES=10: the mutation fuzzer (tests/fuzz/fuzz.py, a seed from the clock, printed
## to replay with --seed; every family: configs, --set, damaged files, studies and the Python
## API; FUZZ_FAMILIES to choose) for MINUTES, then AFL++ on the config entry point for MINUTES
## (tests/fuzz/afl.sh, build-afl; installs AFL++ on demand). Findings: tests/fuzz/README.md
MINUTES ?= 10
FUZZ_FINDINGS ?= fuzz-findings
FUZZ_FAMILIES ?= config,set,file,study,python
fuzz: build
	@bash scripts/install-deps.sh --with-fuzz
	@status=0; \
	$(PYTHON) tests/fuzz/fuzz.py --binary $(BUILD)/granboltz --minutes $(MINUTES) --families $(FUZZ_FAMILIES) \
	  --findings $(FUZZ_FINDINGS) || status=1; \
	JOBS=$(JOBS) bash tests/fuzz/afl.sh $(MINUTES) || status=1; \
	exit $$status

## make bench: whole-run benchmarks (median of REPEAT runs, with the random-number floor) as a
## table and bench/results.csv, then the kernel benchmarks (Google Benchmark), then the tail depth
## f/f(0) per CPU time of constant weights and SWPM (bench/tail_depth.csv)
REPEAT ?= 5
bench: build
	$(BUILD)/bench/granboltz_bench --repeat $(REPEAT) --csv bench/results.csv
	$(BUILD)/bench/granboltz_kernels --benchmark_repetitions=$(REPEAT) --benchmark_report_aggregates_only=true
	$(PYTHON) bench/tail_depth.py --granboltz $(BUILD)/granboltz --csv bench/tail_depth.csv

## make bench-counters: instructions, branch mispredictions and cache misses per event (cachegrind;
## this machine exposes no hardware counters to perf)
bench-counters: build
	/usr/bin/python3 bench/counters.py $(BUILD)/bench/granboltz_bench

## SPARTA=/path/to/spa_serial make bench-peer: the peer problem run by SPARTA and by granboltz,
## interleaved repetition by repetition (median of REPEAT), and the peer table against SPARTA's
## figures (bench/peer.csv, bench/sparta.csv)
bench-peer: build
	@test -n "$(SPARTA)" || { echo "make bench-peer: set SPARTA=/path/to/spa_serial"; exit 2; }
	/usr/bin/python3 bench/peer_interleaved.py $(SPARTA) $(BUILD)/bench/granboltz_bench --repeat $(REPEAT)

## make reproduce: every table and figure at reduced size (config/quick.yaml)
reproduce: deps build python
	snakemake --snakefile workflow/Snakefile --configfile $(PROFILE) --cores $(JOBS) --keep-going

## make check-tables: results/tables/ (after `make reproduce`, quick profile) byte for byte
## against tests/golden/quick_tables/ (see the README to update them on purpose)
check-tables:
	$(PYTHON) tests/golden/check_tables.py results/tables tests/golden/quick_tables

## make format: clang-format (Debian 12's, version 14) on every C++ file; ctest Format checks it
format:
	git ls-files 'src/*.[ch]pp' 'tests/*.[ch]pp' 'bench/*.[ch]pp' 'src/*.h' 'tests/*.h' 'bench/*.h' | xargs clang-format -i

## make check-coverage: the Green–Kubo intervals of eta* and D* over 30 independent replicas
## (their spread over the reported sigma within [0.75, 1.33]; the exact lambda = 0 value covered);
## about 10 minutes on 2 cores, so not part of `make test`
check-coverage: build python
	$(PYTHON) tests/coverage/transport_intervals.py --binary $(BUILD)/granboltz

## make paper: the papers' sizes (config/paper.yaml)
paper: deps build python
	snakemake --snakefile workflow/Snakefile --configfile config/paper.yaml --cores $(JOBS)

clean:
	rm -rf $(BUILD) results/* figures/* logs benchmarks .snakemake
