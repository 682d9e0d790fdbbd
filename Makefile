# granboltz: the two commands a new user needs are `make reproduce` and `make test`.
SHELL := /bin/bash
# Debian's Python first: pyenv's python3 does not see python3-h5py and friends.
export PATH := /usr/bin:$(PATH)
BUILD ?= build
JOBS ?= 2
PROFILE ?= config/quick.yaml

.PHONY: all deps build test test-cpp test-python test-sanitize test-slurm reproduce paper bench sanitize clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

## make test: build, then the C++ suite (ctest) and the Python suite (pytest)
test: deps build test-cpp test-python

test-cpp:
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test-python:
	/usr/bin/python3 -m pytest -q tests/python

## make test-sanitize: the C++ suite built with AddressSanitizer + UndefinedBehaviorSanitizer
## (build-asan; every finding, leaks included, fails the test), without the tests labelled slow
SANITIZE_BUILD ?= build-asan
test-sanitize: deps
	cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGRANBOLTZ_SANITIZE=ON \
	  -DGRANBOLTZ_BENCH=OFF
	cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	cd $(SANITIZE_BUILD) && ctest --output-on-failure -j $(JOBS) -LE slow

## make test-slurm: the SLURM profile against a one-node SLURM started here (munge, slurmctld,
## slurmd; installs slurm-wlm and munge): GRW05 tail shards, merges and a table through the
## profile, one job preempted and resumed, results identical to the local run (exit 77: this
## machine cannot host SLURM)
test-slurm: deps build
	bash scripts/test-slurm.sh

## make bench: whole-run benchmarks (median of REPEAT runs, with the random-number floor) as a
## table and bench/results.csv, then the kernel benchmarks (Google Benchmark)
REPEAT ?= 5
bench: build
	$(BUILD)/bench/granboltz_bench --repeat $(REPEAT) --csv bench/results.csv
	$(BUILD)/bench/granboltz_kernels --benchmark_repetitions=$(REPEAT) --benchmark_report_aggregates_only=true

## make reproduce: every table and figure at reduced size (config/quick.yaml)
reproduce: deps build
	snakemake --snakefile workflow/Snakefile --configfile $(PROFILE) --cores $(JOBS) --keep-going

## make paper: the papers' sizes (config/paper.yaml)
paper: deps build
	snakemake --snakefile workflow/Snakefile --configfile config/paper.yaml --cores $(JOBS)

clean:
	rm -rf $(BUILD) results/* figures/* logs benchmarks .snakemake
