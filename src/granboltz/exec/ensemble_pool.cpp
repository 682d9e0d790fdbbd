#include "granboltz/exec/ensemble_pool.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace granboltz {

namespace {
constexpr auto kFirstReport = std::chrono::seconds(3);
constexpr auto kReportEvery = std::chrono::seconds(10);
// While a run checkpoints, the driver looks this often for a request from a signal handler.
constexpr auto kStopPoll = std::chrono::milliseconds(100);

// Lock-free atomics: set from a signal handler, read by the driver's thread.
std::atomic<bool> g_checkpointing{false};
std::atomic<bool> g_final_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free);

std::string format_seconds(double s) {
  char buf[32];
  if (s < 120)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 7200)
    std::snprintf(buf, sizeof buf, "%.1f min", s / 60);
  else
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  return buf;
}
}  // namespace

bool request_final_checkpoint() noexcept {
  if (!g_checkpointing.load()) return false;
  g_final_requested.store(true);
  return true;
}

bool final_checkpoint_requested() noexcept { return g_final_requested.load(); }

unsigned resolve_threads(unsigned threads, std::uint64_t work_items) {
  unsigned t = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  if (work_items < t) t = static_cast<unsigned>(std::max<std::uint64_t>(1, work_items));
  return t;
}

void for_each_ensemble(const std::vector<std::uint64_t>& ensembles, const DriverOptions& options,
                       const std::function<void(std::uint64_t, ProgressSlot&)>& body) {
  const std::uint64_t total = ensembles.size();
  if (total == 0) return;
  const unsigned nthreads = resolve_threads(options.threads, total);
  std::atomic<std::uint64_t> next{0};
  std::atomic<std::uint64_t> done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable finished;
  unsigned running = nthreads;
  auto slots = std::make_unique<ProgressSlot[]>(nthreads);

  auto worker = [&](unsigned w) {
    for (;;) {
      const std::uint64_t k = next.fetch_add(1);
      if (k >= total || stop.load()) break;
      slots[w].store(0.0);
      try {
        body(ensembles[k], slots[w]);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        stop = true;
        break;
      }
      slots[w].store(0.0);
      done.fetch_add(1);
    }
    std::lock_guard<std::mutex> lock(mutex);
    --running;
    finished.notify_all();
  };

  std::vector<std::thread> pool;
  for (unsigned w = 0; w < nthreads; ++w) pool.emplace_back(worker, w);

  const auto start = std::chrono::steady_clock::now();
  auto next_report = start + kFirstReport;
  const bool ticking = options.tick && options.checkpoint_every > 0;
  const auto tick_every = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(ticking ? options.checkpoint_every : 3600.0));
  auto next_tick = start + tick_every;
  bool reported = false;
  bool cancelled = false;
  const bool polling = ticking || options.cancel || options.fraction;
  auto completed = [&] {
    double fraction = static_cast<double>(done.load());
    for (unsigned w = 0; w < nthreads; ++w) fraction += slots[w].load();
    return fraction / static_cast<double>(total);
  };
  if (ticking) g_checkpointing.store(true);
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (running > 0) {
      const auto wake =
          polling ? std::min({next_report, next_tick, std::chrono::steady_clock::now() + kStopPoll})
                  : next_report;
      if (finished.wait_until(lock, wake, [&] { return running == 0; })) break;
      if (options.fraction) options.fraction->store(completed());
      if (options.cancel && !cancelled && options.cancel->load()) {
        cancelled = true;
        stop = true;
        if (options.on_cancel) {
          lock.unlock();
          options.on_cancel();
          lock.lock();
        }
        continue;
      }
      // A requested final checkpoint is taken like a due one; its callback ends the process.
      if (ticking && !cancelled &&
          (std::chrono::steady_clock::now() >= next_tick || g_final_requested.load())) {
        lock.unlock();
        // Cleared only if it was asked for before this checkpoint: a request that arrives while
        // it is written (after its callback looked) is taken at the next turn, not lost.
        const bool requested = g_final_requested.load();
        std::exception_ptr tick_error;
        try {
          options.tick();  // takes the caller's lock on its record
        } catch (...) {
          tick_error = std::current_exception();
        }
        lock.lock();
        if (requested) g_final_requested.store(false);  // its callback did not end the process
        if (tick_error) {
          if (!error) error = tick_error;
          stop = true;
        }
        next_tick = std::chrono::steady_clock::now() + tick_every;
        continue;
      }
      if (std::chrono::steady_clock::now() < next_report) continue;  // woken only to poll
      if (!options.progress) {
        next_report += kReportEvery;
        continue;
      }
      const double fraction = completed();
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const std::string eta =
          fraction > 0 ? format_seconds(elapsed * (1 - fraction) / fraction) : "?";
      std::fprintf(stderr, "[granboltz] %s: %llu/%llu ensembles, %.1f%%, elapsed %s, eta %s\n",
                   options.label.c_str(), static_cast<unsigned long long>(done.load()),
                   static_cast<unsigned long long>(total), 100 * fraction,
                   format_seconds(elapsed).c_str(), eta.c_str());
      reported = true;
      next_report += kReportEvery;
    }
  }
  g_checkpointing.store(false);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  if (cancelled || (options.cancel && options.cancel->load() && done.load() < total))
    throw RunCancelled();
  if (options.fraction) options.fraction->store(1.0);
  if (reported && options.progress) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "[granboltz] %s: done, %llu ensembles in %s on %u threads\n",
                 options.label.c_str(), static_cast<unsigned long long>(total),
                 format_seconds(elapsed).c_str(), nthreads);
  }
}

}  // namespace granboltz
