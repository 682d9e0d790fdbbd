#pragma once
// Time averages of TV06's event-driven simulations: samples at equal time intervals (TV06 §3.1,
// step 2 of the pseudocode), accumulated per ensemble, and velocity histograms.
#include <cstdint>
#include <vector>

#include "granboltz/tv06/config.hpp"

namespace granboltz::tv06 {

/// Sample times t_k = t0 + k dt, k = 0, 1, ... (computed, not accumulated, so they do not drift).
/// The state is constant between events, so the samples falling before the next event at t
/// all see the current state; TV06's loop "while (t_out < t) { t_out += dt; accumulate }" is
/// `count_before(t)` followed by one weighted accumulation.
class SampleClock {
 public:
  /// `key` names the config key of dt in the error thrown when the samples cannot be counted.
  void start(double t0, double dt, const char* key = "sample_every") {
    t0_ = t0;
    dt_ = dt;
    next_ = 0;
    key_ = key;
  }
  /// The number of sample times in [previous t, t), which are then consumed. Throws
  /// std::runtime_error beyond 2^53 sample times, where t0 + k dt no longer tells k from k + 1.
  std::uint64_t count_before(double t);

 private:
  double time(std::uint64_t k) const { return t0_ + static_cast<double>(k) * dt_; }
  double t0_ = 0.0, dt_ = 1.0;
  std::uint64_t next_ = 0;
  const char* key_ = "sample_every";
};

/// Neumaier's compensated sum: a long time average loses no digits to rounding.
struct CompensatedSum {
  double sum = 0.0, carry = 0.0;
  void add(double x);
  double value() const { return sum + carry; }
};

/// Counts on `bins` equal bins of [-range, range], with the samples outside counted apart.
class Histogram {
 public:
  Histogram() = default;
  explicit Histogram(const VelocityHistogramSpec& spec);
  bool enabled() const { return !counts_.empty(); }
  void add(double x, std::uint64_t weight);
  void merge(const Histogram& other);

  const std::vector<std::uint64_t>& counts() const { return counts_; }
  std::uint64_t below() const { return below_; }  ///< samples with x < -range
  std::uint64_t above() const { return above_; }  ///< samples with x >= range
  /// The bins + 1 bin edges.
  std::vector<double> edges() const;
  double range() const { return range_; }

 private:
  std::vector<std::uint64_t> counts_;
  double range_ = 0.0, scale_ = 0.0;
  std::uint64_t below_ = 0, above_ = 0;
};

}  // namespace granboltz::tv06
