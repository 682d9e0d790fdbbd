// Google Benchmark of the physics kernels and samplers (make bench runs it after the harness).
#include <benchmark/benchmark.h>

#include <vector>

#include "granboltz/physics/collision.hpp"
#include "granboltz/physics/heating.hpp"
#include "granboltz/random/index_stream.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"

using namespace granboltz;

namespace {

void BM_RawEngine(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kEvents);
  for (auto _ : s) benchmark::DoNotOptimize(e());
}
BENCHMARK(BM_RawEngine);

void BM_Uniform01(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kEvents);
  for (auto _ : s) benchmark::DoNotOptimize(uniform01(e));
}
BENCHMARK(BM_Uniform01);

void BM_UniformIndex(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kPairs);
  for (auto _ : s) benchmark::DoNotOptimize(uniform_index(e, 65535));
}
BENCHMARK(BM_UniformIndex);

// An index with its 32 acceptance bits from the blocked lanes of the pairwise majorant.
void BM_IndexStream(benchmark::State& s) {
  IndexStream stream(1, 0, Consumer::kCandidates, 65535);
  const std::vector<double> none(65536, 0.0);
  for (auto _ : s) benchmark::DoNotOptimize(stream.next(none.data(), none.data()));
}
BENCHMARK(BM_IndexStream);

void BM_Normal(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kEvents);
  for (auto _ : s) benchmark::DoNotOptimize(normal(e));
}
BENCHMARK(BM_Normal);

void BM_Exponential(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kEvents);
  for (auto _ : s) benchmark::DoNotOptimize(exponential(e));
}
BENCHMARK(BM_Exponential);

void BM_UnitVector(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kEvents);
  for (auto _ : s) benchmark::DoNotOptimize(unit_vector(e));
}
BENCHMARK(BM_UnitVector);

void BM_CollisionMap(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kEvents);
  Vec3 v{1, 2, 3}, w{-1, 0.5, 2};
  const Vec3 dir = unit_vector(e);
  for (auto _ : s) {
    collide(v, w, dir, 0.5);
    benchmark::DoNotOptimize(v);
    v.x += 1;  // keep the relative speed from decaying to zero
  }
}
BENCHMARK(BM_CollisionMap);

void BM_Kick(benchmark::State& s) {
  Engine e = make_stream(1, 0, Consumer::kSweep);
  Vec3 v{1, 2, 3};
  for (auto _ : s) benchmark::DoNotOptimize(v = white_noise_kick(v, 1.0, 1e-3, e));
}
BENCHMARK(BM_Kick);

}  // namespace

BENCHMARK_MAIN();
