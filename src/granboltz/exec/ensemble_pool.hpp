#pragma once
// Runs independent ensembles on a pool of threads with dynamic scheduling and reports progress
// on stderr. Results never depend on the number of threads: each ensemble draws from its own
// streams and its results are combined with exact, order-independent sums.
#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace granboltz {

class Record;
class H5Writer;

/// Where a running ensemble publishes how far it got, as a fraction in [0, 1].
using ProgressSlot = std::atomic<double>;

struct DriverOptions {
  unsigned threads = 0;           ///< 0: all hardware threads
  bool progress = true;           ///< report on stderr when the run lasts more than a few seconds
  std::string label = "run";      ///< shown in progress lines
  double checkpoint_every = 0.0;  ///< seconds between calls of tick; 0: never
  /// Saves the record of the ensembles completed so far and, through the second argument, the
  /// state of ensembles in progress (set by run_to_file).
  std::function<void(const Record&, const std::function<void(H5Writer&)>&)> checkpoint;
  /// A checkpoint to take the states of ensembles in progress from ("" if none).
  std::string resume_from;
  /// Called from the driver's own thread every checkpoint_every seconds (set by a model's run).
  std::function<void()> tick;
  /// Set from outside (another thread, a signal handler) to stop the run: no ensemble starts
  /// after it, those under way stop at their next safe point if the model supports it (on_cancel;
  /// else when they end), and for_each_ensemble throws RunCancelled. nullptr: never.
  const std::atomic<bool>* cancel = nullptr;
  /// Called once from the driver's thread when it sees `cancel` (set by a model's run).
  std::function<void()> on_cancel;
  /// If given, the driver stores the run's completed fraction in [0, 1] here about every 0.1 s.
  std::atomic<double>* fraction = nullptr;
  /// Called after the final checkpoint that SIGTERM asked for (request_final_checkpoint), from
  /// the driver's thread, instead of ending the process (the CLI's way): a caller that must
  /// not end its process (Python) cancels the run here and ends it itself. Unset: the process
  /// ends with status 128 + SIGTERM.
  std::function<void()> on_final_checkpoint;
};

/// Thrown by a run stopped through DriverOptions::cancel.
struct RunCancelled : std::runtime_error {
  RunCancelled() : std::runtime_error("the run was cancelled") {}
};

/// Calls body(e, slot) for every ensemble e of `ensembles`. The first exception thrown by a
/// body stops the others and is rethrown here.
void for_each_ensemble(const std::vector<std::uint64_t>& ensembles, const DriverOptions& options,
                       const std::function<void(std::uint64_t, ProgressSlot&)>& body);

/// Asks the running for_each_ensemble to take a checkpoint at once (its next safe point) and
/// reports whether one will: true only while a run that checkpoints is under way. Safe in a
/// signal handler (SIGTERM from a batch system before it preempts the job).
bool request_final_checkpoint() noexcept;

/// Whether request_final_checkpoint was accepted: the checkpoint callback then ends the process.
bool final_checkpoint_requested() noexcept;

/// The number of worker threads that `threads` (0 = all) means on this machine.
unsigned resolve_threads(unsigned threads, std::uint64_t work_items);

}  // namespace granboltz
