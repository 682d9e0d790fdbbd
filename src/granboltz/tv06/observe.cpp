#include "granboltz/tv06/observe.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace granboltz::tv06 {

std::uint64_t SampleClock::count_before(double t) {
  if (!(time(next_) < t)) return 0;
  // First guess from the arithmetic, then the exact comparison decides (rounding of (t-t0)/dt).
  const double guess = std::ceil((t - t0_) / dt_);
  if (!(guess < 0x1p53))
    throw std::runtime_error(std::string(key_) + ": more than 2^53 sample times in the run (" +
                             "sample_every far below the time between collisions); choose a "
                             "larger value");
  std::uint64_t end =
      guess > static_cast<double>(next_ + 1) ? static_cast<std::uint64_t>(guess) : next_ + 1;
  while (end > next_ + 1 && !(time(end - 1) < t)) --end;
  while (time(end) < t) ++end;
  const std::uint64_t n = end - next_;
  next_ = end;
  return n;
}

void CompensatedSum::add(double x) {
  const double s = sum + x;
  carry += std::fabs(sum) >= std::fabs(x) ? (sum - s) + x : (x - s) + sum;
  sum = s;
}

Histogram::Histogram(const VelocityHistogramSpec& spec)
    : counts_(spec.bins, 0),
      range_(spec.range),
      scale_(spec.bins ? static_cast<double>(spec.bins) / (2.0 * spec.range) : 0.0) {}

void Histogram::add(double x, std::uint64_t weight) {
  if (counts_.empty() || weight == 0) return;
  if (x < -range_) {
    below_ += weight;
    return;
  }
  if (!(x < range_)) {
    above_ += weight;  // also NaN, which cannot occur but must not index out of range
    return;
  }
  auto k = static_cast<std::size_t>((x + range_) * scale_);
  if (k >= counts_.size()) k = counts_.size() - 1;  // rounding just below +range
  counts_[k] += weight;
}

void Histogram::merge(const Histogram& other) {
  if (other.counts_.size() != counts_.size()) throw std::logic_error("histogram shapes differ");
  for (std::size_t k = 0; k < counts_.size(); ++k) counts_[k] += other.counts_[k];
  below_ += other.below_;
  above_ += other.above_;
}

std::vector<double> Histogram::edges() const {
  std::vector<double> e(counts_.size() + 1);
  const double n = static_cast<double>(counts_.size());
  for (std::size_t k = 0; k < e.size(); ++k)
    e[k] = -range_ + 2.0 * range_ * static_cast<double>(k) / n;
  return e;
}

}  // namespace granboltz::tv06
