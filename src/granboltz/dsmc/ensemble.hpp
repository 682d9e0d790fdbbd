#pragma once
// One ensemble of the DSMC particle system for the heated inelastic Boltzmann equation, advanced
// by one of the three time schemes of RW05: no-splitting (Algorithm 3 = GRW05 §4), Euler
// splitting (Algorithm 1), Strang splitting (Algorithm 2).
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/particles.hpp"
#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/physics/thermostat/list.hpp"
#include "granboltz/random/index_stream.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/record/state_archive.hpp"

namespace granboltz {

/// Events of one ensemble (RW05 §4.2 effort model).
struct EventCounts {
  std::uint64_t collisions = 0;  ///< real collisions
  std::uint64_t fictitious = 0;  ///< rejected candidate pairs
  std::uint64_t kicks = 0;       ///< single-particle kicks (white-noise updates)
};

class DsmcEnsemble {
 public:
  /// Draws the initial Maxwellian and the majorant (GRW05 steps 1.1-1.4).
  /// `progress`, if given, receives the fraction of [0, t_end] simulated so far.
  DsmcEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
               ProgressSlot* progress = nullptr);

  /// Restores an ensemble saved by save() (a checkpoint of an interrupted run).
  DsmcEnsemble(const DsmcConfig& config, const H5Reader& in, const std::string& group,
               ProgressSlot* progress = nullptr);

  /// Advances the system to time s > time(); on return every particle is kicked up to s
  /// (GRW05 Remark 2), ready to be observed (with the Gaussian thermostat, the lazy scale factor
  /// is folded into the velocities first, so that particles() are the true velocities). For the
  /// splitting schemes s must lie on the grid of time steps. If `pause` becomes true, returns
  /// false early at a point between events (or between steps) from which a later call continues
  /// exactly as if it had not stopped.
  bool advance_to(double s, const std::atomic<bool>* pause = nullptr);

  /// Writes the complete state (particles, streams, majorant, counts) under `group`.
  void save(H5Writer& out, const std::string& group) const { save_state(*this, out, group); }
  /// The state, declared once for save() and the restoring constructor: every dataset with its
  /// allowed values (record/state_archive.hpp).
  void visit_state(StateArchive& a);

  /// Replaces every velocity at the current time (granboltz.Simulation's setter; the caller
  /// checks count and finiteness): each particle's clock is set to time(), the majorant's centre
  /// and bound are taken anew as at t = 0, and the Gaussian thermostat rescales the new peculiar
  /// velocities to T0 as it does the initial ones. Exact between calls of advance_to: no waiting
  /// time is pending there.
  void set_velocities(const std::vector<Vec3>& v);

  /// The state at time() can be read without kick_all_to and the fold (see advance_events_to):
  /// no-splitting scheme, no kicks (Gaussian thermostat, none, or white noise with beta = 0), no
  /// flight.
  bool lazy() const { return c_.scheme == Scheme::kNoSplit && !linear_ && !heated_; }
  /// As advance_to, but the event loop only: no kick, no fold of the Gaussian scale, no majorant
  /// update. Only when lazy(); the true velocities are then centre() + scale() (w - centre()).
  bool advance_events_to(double s, const std::atomic<bool>* pause = nullptr);
  double scale() const { return gaussian_ ? std::sqrt(gauss_.s2) : 1.0; }
  /// The mean velocity, conserved by the collisions (and the Gaussian fold).
  const Vec3& centre() const { return v0_; }
  /// With the stress or heat-flux correlation and lazy(): the sums over the stored velocities'
  /// c = w - centre() of c_x^2, c_y^2, c_z^2, c_x c_y, c_x c_z, c_y c_z and c |c|^2 (3), so
  /// that a sample needs no pass over the particles; null otherwise. The first six are kept at
  /// each collision with the stress correlation, the last three with the heat flux; a sum no
  /// correlation reads is exact at the last fold or row only.
  const double* moment_sums() const { return track_ ? sums_.data() : nullptr; }

  const Particles& particles() const { return p_; }
  double time() const { return t_; }
  double u_max() const { return u_max_; }
  const EventCounts& counts() const { return counts_; }
  /// Raw 64-bit random numbers drawn since construction by the event loop and the kicks
  /// (not the initial condition): the work floor that no implementation can go below.
  std::uint64_t random_draws() const;

 private:
  // Collision partners are drawn this many events ahead from their own stream and prefetched;
  // the stream is consumed in order, so the look-ahead cannot change any result.
  static constexpr unsigned kLookahead = 16;
  struct Pair {
    std::uint32_t i, j;  // the partners
    std::uint32_t bits;  // pairwise majorant: the event's 32 acceptance bits
  };

  // The event loops, specialised by what happens between and after collisions: Heat is the
  // thermostat (physics/thermostat/), G the collision geometry (physics/geometry.hpp), which
  // also fixes the dimension.
  template <class Heat, int kLambda, bool kPairwise, class G>
  bool run_nosplit(double s, const std::atomic<bool>* pause);
  template <bool kLazyScale, int kLambda, bool kPairwise, class G>
  void collide_during(double h);  // collision step of length h (splitting schemes)
  // Gaussian thermostat: the stored velocities w relate to the true ones by v = V + s (w - V),
  // V = v0_, s^2 = gauss_.s2 (collisions commute with this map).
  template <int kLambda, bool kPairwise>
  void after_gaussian_collision(double delta);  // delta: the change of sum |w - V|^2
  void set_scale();                             // gauss_.s2 and clock_ from its energy and target
  void fold_scale();  // v := V + s (w - V), then exactly T = T0 about the mean
  void rescale();     // fold_scale() and the majorant in the new units
  template <int kLambda, bool kPairwise>
  Pair select_pair(Engine& pairs);  // candidate pair of the majorant process
  void kick_all_by(double h);       // kicking step of length h (splitting schemes)
  // drag or shear: the majorant's centre 0 (and the shear frame)
  void set_flight_frame();
  bool run_events(double s, const std::atomic<bool>* pause);  // no-splitting, no flight
  void set_tracking();  // which moment sums are kept: once the config and flight are known
  void resum();  // sums_ anew in particle order: at each fold and stop, so round-off cannot build
  void track_pair(const Vec3& a0, const Vec3& b0, const Vec3& a1, const Vec3& b1);
  // shear, nosplit: window_, growth_ and the majorant's factor
  void set_shear_windows();
  void fly_all_to(double s);   // drag or shear: every particle's flight from its time to s
  void start_window();         // shear: the majorant for the window that starts now
  void kick_all_to(double s);  // kick every particle from its own last time to s
  template <int kLambda>
  bool accept(double u2, Engine& events);  // global majorant: real (not fictitious) collision?
  template <int kLambda>
  bool accept_pairwise(double u2, double bound, std::uint32_t bits);
  template <int kLambda>
  double weight(const Vec3& v) const;  // pairwise majorant weight |v - V|^lambda
  template <int kLambda>
  void reweigh(std::uint32_t i);  // refresh w_i, sum and maximum after v_i changed
  template <int kLambda>
  void reweigh_pair(std::uint32_t i, std::uint32_t j);  // both partners, then the rate
  template <int kLambda>
  void reweigh_all();
  void reweigh_all();  // for the runtime lambda
  void set_pairwise_rate();
  void adapt_majorant(const Particle& a);
  void adapt_majorant_scaled(const Particle& a);  // gaussian: for the true velocity of a
  void adapt_majorant_all();
  void set_majorant(double u_max);
  Pair draw_pair(Engine& pairs);
  Pair next_pair(Engine& pairs);
  void set_w_max(double w_max);
  void report(double t) {
    if (progress_) progress_->store(t / c_.t_end, std::memory_order_relaxed);
  }

  const DsmcConfig& c_;
  Particles p_;
  double t_ = 0.0;
  Vec3 v0_;                // bulk velocity at t = 0: the centre of the majorant (GRW05 step 1.3)
  double u_max_ = 0.0;     // U_max
  double u_max2_ = 0.0;    // U_max^2
  double inv_rate_ = 0.0;  // 1 / pi_hat, pi_hat = 2 pi gamma C (n - 1) U_max^lambda
  double adapt_factor2_;   // (1 or 2)^2: paper or strict majorant update
  bool heated_;            // white noise with beta > 0
  bool track_ = false;     // moment_sums() kept (set once the flight is known)
  bool track_stress_ = false, track_heat_ = false;  // which of them: c_a c_b, c |c|^2
  std::array<double, 9> sums_{};
  bool gaussian_;             // dsmc.thermostat: gaussian
  GaussianThermostat gauss_;  // gaussian: the lazy scale's sums and s^2
  double clock_ = 1.0;        // gaussian, pairwise majorant: s^-lambda (the rate is in w units)
  Engine events_, pairs_, sweep_;
  std::array<Pair, kLookahead> ring_{};  // global majorant: the pairs ahead
  unsigned head_ = 0;
  // Pairwise majorant: heavy-partner candidates i, kept if (bits + 1/2) 2^-32 w_max < w_i, and
  // the other partners j', uniform on {0..n-2} (j = j' + (j' >= i)), with the event's acceptance
  // bits.
  IndexStream candidates_, partners_;
  // Pairwise majorant (dsmc.majorant: pairwise): B_ij <= C gamma 4 pi (w_i + w_j).
  bool pairwise_;
  std::vector<double, HugePageAllocator<double>> w_;
  double w_sum_ = 0.0, w_max_ = 0.0;
  double candidate_scale_ = 0.0;         // 2^-32 w_max (exact: a power of two)
  std::uint64_t refresh_countdown_ = 0;  // weight updates until the next exact sweep
  double pairwise_rate_factor_ = 0.0;    // pi_hat / W
  EventCounts counts_;
  ProgressSlot* progress_;
  // Drag or shear (last, off the hot members' cache lines) (physics/flight/): every kick is the
  // flight's exact propagator, the majorant is centred on 0 (the flights contract or shear about
  // it), and with shear it allows for the growth of a speed over one window of the drift (growth_ =
  // its largest factor).
  LinearFlight flight_;
  bool linear_ = false;
  double window_ = 0.0;            // shear: the length of a majorant window
  std::uint64_t next_window_ = 1;  // shear, nosplit: the window that ends at next_window_ * window_
  double growth_ = 1.0;
};

}  // namespace granboltz
