// The pause protocol of exec/safe_points.hpp: a checkpoint parks every ensemble under way and sees
// their states; a cancelled run stops them at their safe point; an ensemble that ended is not
// waited for.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "granboltz/exec/safe_points.hpp"

using namespace granboltz;

namespace {
DriverOptions checkpointing() {
  DriverOptions o;
  o.checkpoint = [](const Record&, const std::function<void(H5Writer&)>&) {};
  return o;
}
/// An ensemble's loop: "advances" until told to stop, parking whenever the flag is up.
void work(SafePoints<int>& safe, std::uint64_t e, const int* state, const std::atomic<bool>& stop,
          std::atomic<int>& rounds) {
  SafePoints<int>::Member member(safe);
  while (!stop) {
    if (safe.pause_flag()->load()) safe.park(e, state);
    ++rounds;
    std::this_thread::yield();
  }
}
}  // namespace

TEST(SafePoints, CheckpointSeesEveryEnsembleParked) {
  SafePoints<int> safe;
  std::vector<std::map<std::uint64_t, const int*>> seen;
  const DriverOptions opts = safe.options(
      checkpointing(),
      [&](const std::map<std::uint64_t, const int*>& parked) { seen.push_back(parked); });
  ASSERT_TRUE(opts.tick && opts.on_cancel);
  const int a = 1, b = 2;
  std::atomic<bool> stop{false};
  std::atomic<int> ra{0}, rb{0};
  std::thread ta(work, std::ref(safe), 3, &a, std::cref(stop), std::ref(ra));
  std::thread tb(work, std::ref(safe), 8, &b, std::cref(stop), std::ref(rb));
  while (ra < 10 || rb < 10) std::this_thread::yield();  // both under way
  opts.tick();
  opts.tick();
  EXPECT_FALSE(safe.pause_flag()->load());  // resumed
  const int before = ra;
  while (ra < before + 10) std::this_thread::yield();  // and going on
  stop = true;
  ta.join();
  tb.join();
  ASSERT_EQ(seen.size(), 2u);
  for (const auto& p : seen) {
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p.at(3), &a);
    EXPECT_EQ(p.at(8), &b);
  }
  // Both ended: a checkpoint waits for none.
  opts.tick();
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_TRUE(seen.back().empty());
}

TEST(SafePoints, CancelStopsEnsemblesAtTheirSafePoint) {
  SafePoints<int> safe;
  const DriverOptions opts = safe.options(DriverOptions{}, [](const auto&) {});
  EXPECT_FALSE(opts.tick);  // no checkpoint, no tick
  const int a = 1;
  std::atomic<bool> stop{false}, threw{false};
  std::atomic<int> rounds{0};
  std::thread t([&] {
    try {
      work(safe, 0, &a, stop, rounds);
    } catch (const RunCancelled&) {
      threw = true;
    }
  });
  while (rounds < 10) std::this_thread::yield();
  opts.on_cancel();
  t.join();
  EXPECT_TRUE(threw);
  EXPECT_TRUE(safe.pause_flag()->load());  // advances keep returning early
}

TEST(SafePoints, AFailedCheckpointResumesTheEnsembles) {
  SafePoints<int> safe;
  const DriverOptions opts =
      safe.options(checkpointing(), [](const auto&) { throw std::runtime_error("disk full"); });
  const int a = 1;
  std::atomic<bool> stop{false};
  std::atomic<int> rounds{0};
  std::thread t(work, std::ref(safe), 0, &a, std::cref(stop), std::ref(rounds));
  while (rounds < 10) std::this_thread::yield();
  EXPECT_THROW(opts.tick(), std::runtime_error);
  EXPECT_FALSE(safe.pause_flag()->load());
  const int before = rounds;
  while (rounds < before + 10) std::this_thread::yield();
  stop = true;
  t.join();
}
