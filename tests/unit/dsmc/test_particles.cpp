// The allocator of the particle arrays: large blocks are mapped, aligned for huge pages, and
// reused by the next ensemble of the same thread, so that a run of many ensembles holds one
// particle array per thread, not one per finished ensemble (glibc's malloc kept them: 19 GB for
// RW05's 10^4 ensembles of 65 536 particles).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <thread>
#include <utility>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/particles.hpp"

using namespace granboltz;

namespace {
/// The resident memory of this process now (not its peak), in bytes.
std::uint64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::uint64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * static_cast<std::uint64_t>(sysconf(_SC_PAGESIZE));
}
}  // namespace

TEST(ParticleAllocator, LargeBlocksAreAlignedAndReusedByTheNextArrayOfTheirSize) {
  const std::size_t huge = (std::size_t{16} << 20) / sizeof(Particle);  // 16 MiB
  const void* first = nullptr;
  {
    Particles p(huge);
    first = p.data();
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p.data()) % (std::size_t{1} << 21), 0u);
    p[huge - 1].t = 1.0;  // the whole block is usable
  }
  {
    Particles p(huge);
    EXPECT_EQ(p.data(), first) << "the freed block was not reused";
    EXPECT_EQ(p[huge - 1].t, 0.0) << "a reused block must still be value-initialised";
    Particles q(huge);  // while the spare is in use: a block of its own
    EXPECT_NE(q.data(), p.data());
  }
  // Mid-sized (mapped, page-aligned) and small (operator new) arrays, grown and shrunk.
  Particles p(10);
  for (std::size_t n = 10; n < (std::size_t{1} << 20); n *= 3) p.resize(n, Particle{{1, 2, 3}, 4});
  EXPECT_EQ(p.front().t, 0.0);
  EXPECT_EQ(p.back().t, 4.0);
  p.shrink_to_fit();
}

TEST(ParticleAllocator, ManyEnsemblesInARowHoldOneParticleArray) {
  // Ensembles built and dropped one after the other on two worker threads, as in the run driver:
  // the resident memory may grow by a few arrays (the spares) and some slack, not by one array
  // per ensemble as it did. 10^5 particles (3.2 MB) and 4096 (128 KiB, the RW05 tables' size).
  for (const auto& [n, count] : {std::pair<int, int>{100000, 60}, {4096, 1000}}) {
    const Config c =
        parse_config("{}", "test",
                     {"model=dsmc", "seed=3", "ensembles=" + std::to_string(count),
                      "dsmc.particles=" + std::to_string(n), "dsmc.kernel.lambda=1",
                      "dsmc.alpha=0.5", "dsmc.beta=1", "dsmc.gamma=1", "dsmc.kernel.C=0.1",
                      "dsmc.t_end=0.001", "dsmc.observe_every=0.001"});
    const std::uint64_t array = c.dsmc.particles * sizeof(Particle);
    // Two worker threads side by side, as in a run on 2 threads, each with its own glibc arena.
    { DsmcEnsemble warm(c.dsmc, c.seed, 0); }
    const std::uint64_t before = resident_bytes();
    auto work = [&](int first) {
      for (int e = first; e < count; e += 2) {
        DsmcEnsemble ens(c.dsmc, c.seed, static_cast<std::uint64_t>(e));
        if (!ens.advance_to(0.001)) return;
      }
    };
    std::thread one(work, 1), two(work, 2);
    one.join();
    two.join();
    const std::uint64_t after = resident_bytes();
    ASSERT_GT(after, 0u);
    EXPECT_LT(after, before + 6 * array + (std::uint64_t{1} << 20))
        << "n = " << n << ": resident memory grew from " << before << " to " << after
        << " bytes over " << count - 1 << " ensembles";
  }
}
