#include "granboltz/stats/correlator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace granboltz {

void MultipleTauCorrelator::check(const Resolution& r) {
  if (r.points < 2 || r.points % 2 != 0 || r.points > 1024)
    throw std::invalid_argument("points = " + std::to_string(r.points) +
                                ": must be even and in [2, 1024]");
  if (r.averaging < 2 || r.points % r.averaging != 0)
    throw std::invalid_argument("averaging = " + std::to_string(r.averaging) +
                                ": must be at least 2 and divide points (" +
                                std::to_string(r.points) + ")");
  if (r.levels < 1 || std::log2(static_cast<double>(r.averaging)) * (r.levels - 1) > 62)
    throw std::invalid_argument("levels = " + std::to_string(r.levels) +
                                ": must be at least 1, with averaging^(levels-1) below 2^62");
}

std::uint64_t MultipleTauCorrelator::lag_count(const Resolution& r) {
  return r.points + std::uint64_t{r.levels - 1} * (r.points - r.points / r.averaging);
}

double MultipleTauCorrelator::longest_lag(const Resolution& r) {
  return (r.points - 1.0) * std::pow(static_cast<double>(r.averaging), r.levels - 1.0);
}

MultipleTauCorrelator::MultipleTauCorrelator(std::uint64_t channels, Resolution resolution)
    : C_(channels), r_(resolution) {
  check(r_);
  if (C_ == 0) throw std::invalid_argument("a correlator needs at least one channel");
  const std::uint64_t K = r_.levels, p = r_.points;
  s_.shift.assign(K * p * C_, 0.0);
  s_.block.assign(K * C_, 0.0);
  s_.fill.assign(K, 0);
  s_.in_block.assign(K, 0);
  s_.sum.assign(K * p, 0.0);
  s_.count.assign(K * p, 0);
  head_.assign(K, 0);
}

MultipleTauCorrelator::MultipleTauCorrelator(std::uint64_t channels, Resolution resolution,
                                             State state)
    : MultipleTauCorrelator(channels, resolution) {
  auto refuse = [](const std::string& what) {
    throw std::invalid_argument("correlator state: " + what);
  };
  if (state.shift.size() != s_.shift.size()) refuse("shift register of the wrong size");
  if (state.block.size() != s_.block.size()) refuse("block sums of the wrong size");
  if (state.fill.size() != s_.fill.size() || state.in_block.size() != s_.in_block.size())
    refuse("level counters of the wrong size");
  if (state.sum.size() != s_.sum.size() || state.count.size() != s_.count.size())
    refuse("lag sums of the wrong size");
  for (std::uint64_t k = 0; k < r_.levels; ++k) {
    if (state.fill[k] > r_.points) refuse("a level filled beyond its points");
    if (state.in_block[k] >= r_.averaging) refuse("a block holding averaging values or more");
  }
  for (const double x : state.shift)
    if (!std::isfinite(x)) refuse("a non-finite value");
  for (const double x : state.block)
    if (!std::isfinite(x)) refuse("a non-finite block sum");
  for (const double x : state.sum)
    if (!std::isfinite(x)) refuse("a non-finite lag sum");
  s_ = std::move(state);
}

void MultipleTauCorrelator::add(std::span<const double> sample) {
  if (sample.size() != C_)
    throw std::invalid_argument("a sample of " + std::to_string(sample.size()) +
                                " values for a correlator of " + std::to_string(C_) + " channels");
  push(0, sample.data());
}

namespace {
// Four partial sums in a fixed order (channel c into sum c mod 4, the last n mod 4 into the
// first; then (s0 + s1) + (s2 + s3)):
// the same bits on any machine, and four times the throughput of one running sum, whose every
// addition waits for the one before.
double dot_product(const double* a, const double* b, std::uint64_t n) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  std::uint64_t c = 0;
  for (; c + 4 <= n; c += 4) {
    s0 += a[c] * b[c];
    s1 += a[c + 1] * b[c + 1];
    s2 += a[c + 2] * b[c + 2];
    s3 += a[c + 3] * b[c + 3];
  }
  for (; c < n; ++c) s0 += a[c] * b[c];
  return (s0 + s1) + (s2 + s3);
}
}  // namespace

void MultipleTauCorrelator::push(unsigned k, const double* value) {
  const std::uint64_t p = r_.points, C = C_;
  double* shift = s_.shift.data() + k * p * C;
  // A ring: the new value takes the slot before the newest one (the oldest's, once full), so
  // no value moves; the value j samples older is in slot (head + j) mod p.
  const std::uint64_t head = head_[k] = (head_[k] + p - 1) % p;
  std::copy(value, value + C, shift + head * C);
  s_.fill[k] = std::min<std::uint64_t>(s_.fill[k] + 1, p);
  // Lags below p/m of the levels above 0 are the level below's, at a finer resolution.
  const std::uint64_t first = k == 0 ? 0 : p / r_.averaging;
  double* sum = s_.sum.data() + k * p;
  std::uint64_t* count = s_.count.data() + k * p;
  for (std::uint64_t j = first; j < s_.fill[k]; ++j) {
    const double* older = shift + ((head + j) % p) * C;
    sum[j] += dot_product(shift + head * C, older, C);
    ++count[j];
  }
  if (k + 1 >= r_.levels) return;
  double* block = s_.block.data() + k * C;
  for (std::uint64_t c = 0; c < C; ++c) block[c] += value[c];
  if (++s_.in_block[k] < r_.averaging) return;
  const double m = r_.averaging;
  for (std::uint64_t c = 0; c < C; ++c) block[c] /= m;
  push(k + 1, block);
  std::fill(block, block + C, 0.0);
  s_.in_block[k] = 0;
}

MultipleTauCorrelator::State MultipleTauCorrelator::state() const {
  State out = s_;
  const std::uint64_t p = r_.points, C = C_;
  for (std::uint64_t k = 0; k < r_.levels; ++k) {
    const double* ring = s_.shift.data() + k * p * C;
    double* first = out.shift.data() + k * p * C;
    for (std::uint64_t j = 0; j < p; ++j)
      std::copy(ring + ((head_[k] + j) % p) * C, ring + ((head_[k] + j) % p + 1) * C,
                first + j * C);
  }
  return out;
}

std::vector<std::uint64_t> MultipleTauCorrelator::lags() const {
  std::vector<std::uint64_t> out;
  std::uint64_t unit = 1;
  for (std::uint64_t k = 0; k < r_.levels; ++k, unit *= r_.averaging)
    for (std::uint64_t j = k == 0 ? 0 : r_.points / r_.averaging; j < r_.points; ++j)
      out.push_back(j * unit);
  return out;
}

std::vector<std::uint64_t> MultipleTauCorrelator::origins() const {
  std::vector<std::uint64_t> out;
  for (std::uint64_t k = 0; k < r_.levels; ++k)
    for (std::uint64_t j = k == 0 ? 0 : r_.points / r_.averaging; j < r_.points; ++j)
      out.push_back(s_.count[k * r_.points + j]);
  return out;
}

std::vector<double> MultipleTauCorrelator::correlation() const {
  std::vector<double> out;
  const double C = static_cast<double>(C_);
  for (std::uint64_t k = 0; k < r_.levels; ++k)
    for (std::uint64_t j = k == 0 ? 0 : r_.points / r_.averaging; j < r_.points; ++j) {
      const std::uint64_t n = s_.count[k * r_.points + j];
      out.push_back(n ? s_.sum[k * r_.points + j] / (static_cast<double>(n) * C)
                      : std::numeric_limits<double>::quiet_NaN());
    }
  return out;
}

}  // namespace granboltz
