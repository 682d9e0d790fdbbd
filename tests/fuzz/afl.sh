#!/usr/bin/env bash
# make fuzz, the coverage-guided half: AFL++ on the config entry point (tests/fuzz/afl_config.cpp)
# for MINUTES, in its own build directory; prints each crash or hang and how to replay it.
# Usage: tests/fuzz/afl.sh MINUTES
set -euo pipefail
cd "$(dirname "$0")/../.."
MINUTES=${1:-10}
BUILD_AFL=${BUILD_AFL:-build-afl}
for tool in afl-fuzz afl-clang-fast++; do
  command -v "$tool" >/dev/null || {
    echo "fuzz: $tool not found: install AFL++ with bash scripts/install-deps.sh --with-fuzz" >&2
    exit 2
  }
done
cmake -S . -B "$BUILD_AFL" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=afl-clang-fast \
  -DCMAKE_CXX_COMPILER=afl-clang-fast++ -DGRANBOLTZ_AFL=ON -DGRANBOLTZ_TESTS=OFF \
  -DGRANBOLTZ_BENCH=OFF >/dev/null
AFL_QUIET=1 cmake --build "$BUILD_AFL" -j "${JOBS:-2}" --target granboltz_afl_config >/dev/null
harness="$BUILD_AFL/granboltz_afl_config"

# Seeds: the bad-input corpus and the valid configs, and one with overrides ("#set " lines).
seeds="$BUILD_AFL/afl-seeds"
rm -rf "$seeds" && mkdir -p "$seeds"
cp tests/bad_inputs/*.yaml "$seeds/"
for f in tests/bad_inputs/base/*.yaml; do cp "$f" "$seeds/base_$(basename "$f")"; done
{ cat tests/bad_inputs/base/dsmc.yaml; printf '#set dsmc.scheme=strang\n#set dsmc.steps=2\n'; } \
  >"$seeds/base_dsmc_set.yaml"
out="$BUILD_AFL/afl-out-$(date +%Y%m%d-%H%M%S)"
seconds=$(awk -v m="$MINUTES" 'BEGIN { s = int(m * 60); print (s < 10 ? 10 : s) }')
echo "fuzz: AFL++ on parse_config for $MINUTES min: $out"
AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1 AFL_NO_AFFINITY=1 \
  afl-fuzz -V "$seconds" -i "$seeds" -o "$out" -x tests/fuzz/config.dict -t 2000 \
  -m none -- "$harness" >"$out.log" 2>&1 || { tail -20 "$out.log"; exit 1; }

stats="$out/default/fuzzer_stats"
get() { awk -F' *: *' -v k="$1" '$1 == k {print $2}' "$stats"; }
echo "fuzz: AFL++ ran $(get execs_done) executions ($(get execs_per_sec)/s), $(get corpus_count) paths, \
$(get saved_crashes) crashes, $(get saved_hangs) hangs (log: $out.log)"
found=0
for f in "$out"/default/crashes/id:* "$out"/default/hangs/id:*; do
  [ -e "$f" ] || continue
  found=1
  echo "fuzz: FINDING $f"
  echo "      replay: $harness '$f'   (or: build/granboltz validate '$f')"
done
exit $found
