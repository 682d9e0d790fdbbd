// The blocked index streams of the pairwise majorant: uniform indices (Lemire's exact rejection,
// also where it rejects often), independent uniform bits, the weighted selection, and the lanes
// stepped together giving the numbers of xoshiro256++ itself.
#include <gsl/gsl_cdf.h>
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "granboltz/random/index_stream.hpp"
#include "granboltz/random/rng.hpp"

using namespace granboltz;

namespace {
double chi_square(const std::vector<double>& counts, const std::vector<double>& p, double n) {
  double chi2 = 0;
  for (std::size_t k = 0; k < counts.size(); ++k)
    chi2 += (counts[k] - n * p[k]) * (counts[k] - n * p[k]) / (n * p[k]);
  return chi2;
}
const double kNone[1] = {0.0};  // nothing to prefetch
}  // namespace

TEST(IndexStream, LanesGiveTheNumbersOfTheirOwnEngines) {
  // The vector step is xoshiro256++ itself: the k-th index comes from the k-th number of the
  // interleaved lanes, lane l being make_stream(..., l). With range 1000 Lemire's method rejects
  // with probability 7e-8, so none of these is redrawn.
  const std::uint32_t range = 1000;
  IndexStream s(5, 2, Consumer::kCandidates, range);
  std::array<Engine, IndexStream::kLanes> lanes;
  for (unsigned l = 0; l < IndexStream::kLanes; ++l)
    lanes[l] = make_stream(5, 2, Consumer::kCandidates, l);
  for (unsigned k = 0; k < 5 * IndexStream::kBlock; ++k) {
    const IndexBits x = s.next(kNone, kNone);
    const std::uint64_t r = lanes[k % IndexStream::kLanes]();
    ASSERT_EQ(x.bits, static_cast<std::uint32_t>(r)) << k;
    ASSERT_EQ(x.i, static_cast<std::uint32_t>(((r >> 32) * range) >> 32)) << k;
  }
  EXPECT_EQ(s.draws(), 6u * IndexStream::kBlock);  // the stream draws one block ahead
}

TEST(IndexStream, IndicesAreUniformAlsoWhereLemireRejectsOften) {
  // range 7, and 3 2^30, where a quarter of the raw draws are rejected and redrawn from lane 0.
  for (const std::uint32_t range : {7u, 3u << 30}) {
    IndexStream s(1, 0, Consumer::kPartners, range);
    const double n = 700000;
    std::vector<double> index(7, 0.0), bits(8, 0.0);
    for (int k = 0; k < static_cast<int>(n); ++k) {
      const IndexBits x = s.next(kNone, kNone);
      ASSERT_LT(x.i, range);
      index[range == 7 ? x.i : x.i >> 30] += 1;
      bits[x.bits >> 29] += 1;
    }
    if (range != 7) index.resize(3);
    const std::vector<double> p_index(index.size(), 1.0 / static_cast<double>(index.size()));
    EXPECT_LT(chi_square(index, p_index, n), gsl_cdf_chisq_Qinv(0.001, index.size() - 1.0))
        << range;
    EXPECT_LT(chi_square(bits, std::vector<double>(8, 0.125), n), gsl_cdf_chisq_Qinv(0.001, 7))
        << range;
    if (range != 7) EXPECT_GT(s.draws(), n * 1.3) << "the rejections were not redrawn";
  }
}

TEST(IndexStream, SelectDrawsIndicesInProportionToTheirWeights) {
  const std::vector<double> w = {0.0, 1.0, 2.0, 3.0, 0.5, 3.5};  // sum 10, max 3.5
  IndexStream s(9, 1, Consumer::kCandidates, static_cast<std::uint32_t>(w.size()));
  const double n = 600000;
  std::vector<double> counts(w.size(), 0.0), p(w.size());
  for (int k = 0; k < static_cast<int>(n); ++k)
    counts[s.select(w.data(), w.data(), 0x1p-32 * 3.5)] += 1;
  EXPECT_EQ(counts[0], 0.0);
  for (std::size_t k = 1; k < w.size(); ++k) p[k] = w[k] / 10.0;
  counts.erase(counts.begin());
  p.erase(p.begin());
  EXPECT_LT(chi_square(counts, p, n), gsl_cdf_chisq_Qinv(0.001, 4));
}
