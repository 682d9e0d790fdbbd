#pragma once
// The multiple-tau correlator (Ramírez, Sukumaran, Vorselaars & Likhtman, J. Chem. Phys. 133,
// 154103 (2010); LAMMPS `fix ave/correlate/long`): the time autocorrelation of a signal of C
// channels sampled at equal intervals, at lags from one sample to ~p m^(K-1) samples in bounded
// memory (K levels of p values per channel).
//
// Level 0 holds the last p samples and correlates lags 0..p-1 exactly. Every m values of level k
// are averaged into one value of level k+1, which correlates lags j m^(k+1), j = p/m..p-1 (the
// shorter lags are level k's). So lag j m^k of level k is the exact correlation of the signal
// averaged over blocks of m^k samples: exact at level 0, smoothed over the block at higher levels
// (a relative error of order (m^k / correlation time)^2 where the correlation is smooth).
//
// The result is the mean over channels and over time origins, (1/C) sum_c <A_c(t) A_c(t+tau)>:
// for a velocity autocorrelation the channels are the n d velocity components, for a stress
// autocorrelation the equivalent off-diagonal components. The sums are taken in a fixed order,
// so the same samples give the same bits, and the whole state can be saved and restored.
#include <cstdint>
#include <span>
#include <vector>

namespace granboltz {

class MultipleTauCorrelator {
 public:
  /// The resolution: p values per level (even, >= 2), blocks of m values averaged into the next
  /// level (m >= 2, dividing p), K levels (>= 1). Throws std::invalid_argument otherwise.
  struct Resolution {
    unsigned points = 16;
    unsigned averaging = 2;
    unsigned levels = 12;
  };

  /// Everything the correlator holds, for checkpoints: with the same resolution and channels,
  /// restoring it and adding the same samples gives the same bits as never stopping.
  struct State {
    std::vector<double> shift;  ///< [K][p][C]: level k's values, newest first
    std::vector<double> block;  ///< [K][C]: the running sum of the block being averaged
    std::vector<std::uint64_t>
        fill;  ///< [K]: values that entered level k (capped at p: it is full)
    std::vector<std::uint64_t> in_block;  ///< [K]: values summed into block k (< m)
    std::vector<double> sum;           ///< [K][p]: sum over origins and channels of A(t) A(t + lag)
    std::vector<std::uint64_t> count;  ///< [K][p]: origins summed
  };

  MultipleTauCorrelator(std::uint64_t channels, Resolution resolution);
  /// Restores a saved state; throws std::invalid_argument naming the part that does not fit.
  MultipleTauCorrelator(std::uint64_t channels, Resolution resolution, State state);

  /// Adds one sample (channels() values). Throws std::invalid_argument on a wrong size.
  void add(std::span<const double> sample);

  std::uint64_t channels() const { return C_; }
  const Resolution& resolution() const { return r_; }
  /// The state with each level's values newest first (the order a restore expects).
  State state() const;

  /// The lags, in samples, in increasing order: 0..p-1, then j m^k for k >= 1, j = p/m..p-1.
  std::vector<std::uint64_t> lags() const;
  /// The correlation at each of lags(): (1/C) sum_c mean over origins of A_c(t) A_c(t + lag);
  /// NaN at a lag no origin has reached yet.
  std::vector<double> correlation() const;
  /// The number of time origins averaged at each of lags().
  std::vector<std::uint64_t> origins() const;

  /// The number of lags for a resolution: p + (K - 1)(p - p/m).
  static std::uint64_t lag_count(const Resolution& r);
  /// The longest lag, in samples: (p - 1) m^(K-1).
  static double longest_lag(const Resolution& r);
  /// Throws std::invalid_argument (naming `points`, `averaging` or `levels`) for a bad resolution.
  static void check(const Resolution& r);

 private:
  void push(unsigned level, const double* value);

  std::uint64_t C_;
  Resolution r_;
  State s_;  // shift held as a ring per level: the newest value of level k in slot head_[k]
  std::vector<std::uint64_t> head_;
};

}  // namespace granboltz
