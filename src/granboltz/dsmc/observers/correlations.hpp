#pragma once
// Time correlations (dsmc.correlations): sampled between the observation rows at their own
// interval, each by a multiple-tau correlator (stats/correlator.hpp) per ensemble, in bounded
// memory. The signals, with c = v - V the peculiar velocity, T the ensemble's temperature and m
// the particle's mass:
//   velocity      c_i of the first `particles` particles of each species (channels: their d
//                 components): the velocity autocorrelation, whose integral is self-diffusion;
//   stress        sum_i m c_ia c_ib / sqrt(n), a < b (xy, xz, yz; in d = 2 xy), and beside it
//   normal_stress sum_i m (c_ia^2 - c_ib^2) / (2 sqrt(n)) for (a, b) = (x, y), (y, z), (z, x)
//                 (in d = 2 (x, y)): in an isotropic state each has the off-diagonal components'
//                 autocorrelation, so both give the shear viscosity;
//   heat_flux     sum_i c_i (m |c_i|^2 / 2 - (d + 2) T / 2) / sqrt(n).
// The 1/sqrt(n) keeps the collective signals' lag-0 value intensive: for a Maxwellian at T, about
// T^2 for the stress and (d + 2) T^3 / 2 per component for the heat flux.
//
// Each ensemble's correlation C_e(lag), averaged over channels and time origins, is normalised
// by its own lag 0: rho_e = C_e / C_e(0). The record sums rho_e at every lag, their products at
// every pair of lags (the covariance a Green-Kubo integral's interval needs) and C_e(0); the
// output is /correlations/<name>/{lag, mean, ci, covariance, lag0, lag0_ci}.
#include <string>
#include <vector>

#include "granboltz/dsmc/observers/observer.hpp"
#include "granboltz/stats/correlator.hpp"

namespace granboltz {

class CorrelationsObserver final : public Observer {
 public:
  explicit CorrelationsObserver(const DsmcConfig& d);

  const char* name() const override { return "correlations"; }
  void declare(Record& record, LayoutPhase phase) const override;
  ObserverRows start(bool weighted) const override;
  double next_sample(const ObserverRows& rows) const override;
  void sample(const ParticleView& view, double t, ObserverRows& rows) const override;
  void save(H5Writer& out, const std::string& group, const ObserverRows& rows,
            std::uint64_t next) const override;
  ObserverRows load(const H5Reader& in, const std::string& group, bool weighted,
                    std::uint64_t next) const override;
  void accumulate(const FinishedEnsemble& ensemble, const ObserverRows& rows,
                  Record& record) const override;
  void present(Presenter& out, const Record& record) const override;

 private:
  enum Signal { kVelocity, kStress, kNormalStress, kHeatFlux };
  /// One correlator of every ensemble: its signal, the spec that schedules it, its output group.
  struct Channel {
    Signal signal;
    int spec;             ///< 0 velocity, 1 stress, 2 heat flux: the schedule in rows.counts
    std::size_t species;  ///< velocity: the species whose tagged particles it follows
    std::uint64_t width;  ///< the correlator's channels
    std::string path;     ///< /correlations/<name>[/<species>]
    std::string key;      ///< its sums' name in the record
  };
  const CorrelationSpec& spec(int k) const;
  double sample_time(int k, std::uint64_t index) const;
  MultipleTauCorrelator::Resolution resolution(int k) const;

  const DsmcConfig& d_;
  std::vector<Channel> channels_;
};

}  // namespace granboltz
