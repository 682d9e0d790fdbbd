#pragma once
// How ensembles under way stop at a safe point: for a mid-run checkpoint (every ensemble parks,
// the checkpoint saves the parked states, they go on) and for a cancelled run (SIGINT, a Python
// pause: they stop and the run throws RunCancelled). One lock serves this and the caller's
// record, so that a checkpoint sees the record and the parked states of one instant.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>

#include "granboltz/exec/ensemble_pool.hpp"

namespace granboltz {

/// `State`: what an ensemble under way hands to a checkpoint while it is parked.
template <class State>
class SafePoints {
 public:
  /// The lock of the protocol, which the caller also holds to change its record.
  std::mutex& mutex() { return mutex_; }
  /// The flag an ensemble's advance polls: set, it returns early at its next safe point.
  const std::atomic<bool>* pause_flag() const { return &pause_; }

  /// `options` with on_cancel, and with a checkpoint a tick that parks every ensemble under way,
  /// calls save(parked) (a map from ensemble to State*) under the lock, and resumes them.
  template <class Save>
  DriverOptions options(const DriverOptions& options, Save save) {
    DriverOptions opts = options;
    opts.on_cancel = [this] {
      std::lock_guard<std::mutex> lock(mutex_);
      cancelled_ = true;
      pause_ = true;
      changed_.notify_all();
    };
    if (options.checkpoint)
      opts.tick = [this, save] {
        std::unique_lock<std::mutex> lock(mutex_);
        pause_ = true;
        changed_.wait(lock, [&] { return static_cast<int>(parked_.size()) == active_; });
        try {
          save(parked_);
        } catch (...) {
          pause_ = false;
          changed_.notify_all();
          throw;
        }
        pause_ = false;
        changed_.notify_all();
      };
    return opts;
  }

  /// An ensemble counted as under way from construction until leave() (or, however it ends, an
  /// exception included, its destruction), so that a checkpoint never waits for one that ended.
  class Member {
   public:
    explicit Member(SafePoints& p) : p_(p) {
      std::lock_guard<std::mutex> lock(p_.mutex_);
      ++p_.active_;
    }
    Member(const Member&) = delete;
    Member& operator=(const Member&) = delete;
    /// With the lock held.
    void leave() {
      if (!done_) --p_.active_, p_.changed_.notify_all(), done_ = true;
    }
    ~Member() {
      if (done_) return;
      std::lock_guard<std::mutex> lock(p_.mutex_);
      leave();
    }

   private:
    SafePoints& p_;
    bool done_ = false;
  };

  /// Called by ensemble e when its advance returned early: parks with its state until the pause
  /// ends; throws RunCancelled if the run was cancelled.
  void park(std::uint64_t e, const State* state) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (cancelled_) throw RunCancelled();
    parked_[e] = state;
    changed_.notify_all();
    changed_.wait(lock, [&] { return !pause_.load() || cancelled_; });
    parked_.erase(e);
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::atomic<bool> pause_{false};
  int active_ = 0;
  std::map<std::uint64_t, const State*> parked_;
  bool cancelled_ = false;  // DriverOptions::cancel: the ensembles under way stop at a safe point
};

}  // namespace granboltz
