// Random streams addressed by (seed, ensemble, consumer): reproducible and distinct.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "granboltz/random/rng.hpp"

using namespace granboltz;

TEST(RandomStreams, TheSameAddressGivesTheSameSequence) {
  Engine a = make_stream(7, 3, Consumer::kEvents);
  Engine b = make_stream(7, 3, Consumer::kEvents);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a(), b());
}

TEST(RandomStreams, EveryComponentOfTheAddressChangesTheStream) {
  std::set<std::uint64_t> firsts;
  for (std::uint64_t seed : {0, 1, 2})
    for (std::uint64_t ens : {0, 1, 1000000})
      for (Consumer c : {Consumer::kInitial, Consumer::kEvents, Consumer::kPairs, Consumer::kSweep})
        firsts.insert(make_stream(seed, ens, c)());
  EXPECT_EQ(firsts.size(), 3u * 3u * 4u);
}

TEST(RandomStreams, NeighbouringEnsemblesAreUncorrelated) {
  // Correlation of uniform variates of ensembles 0 and 1: sd 1/sqrt(12 n) for independent ones.
  Engine a = make_stream(1, 0, Consumer::kEvents), b = make_stream(1, 1, Consumer::kEvents);
  const int n = 100000;
  double sab = 0;
  for (int i = 0; i < n; ++i) {
    const double x = static_cast<double>(a() >> 11) * 0x1p-53 - 0.5;
    const double y = static_cast<double>(b() >> 11) * 0x1p-53 - 0.5;
    sab += x * y;
  }
  const double corr = sab / n * 12.0;
  EXPECT_LT(std::fabs(corr), 4.0 / std::sqrt(static_cast<double>(n)));
}

TEST(RandomStreams, GoldenValuesPinTheStreamDerivation) {
  // Changing the derivation would silently change every published result: pin it.
  Engine e = make_stream(12345, 6, Consumer::kEvents);
  const std::uint64_t first = e();
  const std::uint64_t second = e();
  Engine again = make_stream(12345, 6, Consumer::kEvents);
  EXPECT_EQ(again(), first);
  EXPECT_EQ(first, 10917151307012424808ULL);
  EXPECT_EQ(second, 6239882873227188105ULL);
}

TEST(RandomStreams, EngineReproducesTheReferenceXoshiro256PlusPlusOutput) {
  // First outputs of the reference implementation (Blackman & Vigna) from the state {1, 2, 3, 4}.
  Engine e({1, 2, 3, 4});
  const std::uint64_t expected[] = {41943041ULL,
                                    58720359ULL,
                                    3588806011781223ULL,
                                    3591011842654386ULL,
                                    9228616714210784205ULL,
                                    9973669472204895162ULL};
  for (std::uint64_t x : expected) EXPECT_EQ(e(), x);
  EXPECT_EQ(e.draws(), 6u);
}
