#pragma once
// The exact state of a run's results: everything its output datasets are computed from.
//
// A Record holds exact sums over ensembles (fixed-point moment sums, integer histogram counts
// and their squares, integer totals) and per-ensemble columns keyed by the ensemble index.
// Adding ensembles in any order, merging the records of shards, or reading a record back from a
// file and continuing gives the same bits: the output of a run, of a merge of its shards and of a
// resumed run are therefore identical.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "granboltz/core/int128.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/stats/statistics.hpp"

namespace granboltz {

class Record {
 public:
  /// While one is alive on this thread, declare_moments and declare_counts allocate nothing and
  /// add their sizes here instead: what a layout will hold, found by building it (the cost
  /// estimate and the memory check use it, so they count every accumulator a layout declares).
  struct Sizing {
    std::uint64_t moments = 0;  ///< moment sums (Moments2)
    std::uint64_t counts = 0;   ///< integer counts (with their squares)
    Sizing();
    ~Sizing();
    Sizing(const Sizing&) = delete;
    Sizing& operator=(const Sizing&) = delete;

   private:
    Sizing* previous_;
  };

  /// Declares a group of `size` moment sums stored at /accumulators/<name>.
  void declare_moments(const std::string& name, std::size_t size);
  /// Declares `size` integer counts (and their squares) stored at /accumulators/<name>.
  void declare_counts(const std::string& name, std::size_t size);
  /// Declares an integer total stored as an attribute of /accumulators.
  void declare_total(const std::string& name);
  /// Declares a per-ensemble column stored at `path` (e.g. /events/collisions).
  void declare_column(const std::string& path, bool floating);

  std::vector<Moments2>& moments(const std::string& name) { return moments_.at(name); }
  const std::vector<Moments2>& moments(const std::string& name) const { return moments_.at(name); }
  /// Adds one ensemble's counts to the sums of counts and of squared counts.
  void add_counts(const std::string& name, const std::vector<std::uint64_t>& counts);
  const std::vector<std::uint64_t>& counts(const std::string& name) const;
  const std::vector<uint128>& counts_sq(const std::string& name) const;
  std::uint64_t& total(const std::string& name) { return totals_.at(name); }
  std::uint64_t total(const std::string& name) const { return totals_.at(name); }

  /// Registers ensemble e with its per-ensemble values (in the order the columns were declared).
  /// Throws if e is already present.
  void add_ensemble(std::uint64_t e, const std::vector<double>& values);
  bool has_ensemble(std::uint64_t e) const { return rows_.count(e) > 0; }
  std::uint64_t ensembles() const { return rows_.size(); }
  /// Ensemble indices in increasing order.
  std::vector<std::uint64_t> ensemble_indices() const;
  /// A column in ensemble order.
  std::vector<double> column(const std::string& path) const;

  /// Adds another record of the same layout; throws std::runtime_error naming the first ensemble
  /// present in both.
  void merge(const Record& other);

  /// Writes the sums (/accumulators) and the columns (with /events/ensemble).
  void write(H5Writer& out) const;
  /// Reads the sums and columns of a record of this layout from a file; throws
  /// std::runtime_error naming what is missing or malformed.
  void read(const H5Reader& in);

 private:
  struct Counts {
    std::vector<std::uint64_t> sum;
    std::vector<uint128> sum_sq;
  };
  struct Column {
    std::string path;
    bool floating;
  };
  std::map<std::string, std::vector<Moments2>> moments_;
  std::map<std::string, Counts> counts_;
  std::map<std::string, std::uint64_t> totals_;
  std::vector<Column> columns_;
  std::map<std::uint64_t, std::vector<double>> rows_;  // ensemble -> column values
};

}  // namespace granboltz
