// The allocator of the particle arrays: large blocks are mapped, aligned for huge pages, and
// reused by the next ensemble of the same thread, so that a run of many ensembles holds one
// particle array per thread, not one per finished ensemble (glibc's malloc kept them: 19 GB for
// RW05's 10^4 ensembles of 65 536 particles).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <thread>

#include "granboltz/config/config.hpp"
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
  // 60 ensembles of 10^5 particles (3.2 MB each) built and dropped one after the other: the
  // resident memory may grow by a few arrays (the first touch of the spare, the weights), not by
  // one per ensemble as it did.
  const Config c = parse_config("{}", "test",
                                {"model=dsmc", "seed=3", "ensembles=60", "dsmc.particles=100000",
                                 "dsmc.kernel.lambda=1", "dsmc.alpha=0.5", "dsmc.beta=1", "dsmc.gamma=1", "dsmc.kernel.C=0.1", "dsmc.t_end=0.001",
                                 "dsmc.observe_every=0.001"});
  const std::uint64_t array = c.dsmc.particles * sizeof(Particle);
  std::uint64_t before = 0, after = 0;
  // On a worker thread, as in the run driver: glibc gives it an arena of its own.
  std::thread worker([&] {
    { DsmcEnsemble warm(c.dsmc, c.seed, 0); }
    before = resident_bytes();
    for (std::uint64_t e = 1; e < 60; ++e) {
      DsmcEnsemble ens(c.dsmc, c.seed, e);
      if (!ens.advance_to(0.001)) return;
    }
    after = resident_bytes();
  });
  worker.join();
  ASSERT_GT(after, 0u);
  EXPECT_LT(after, before + 4 * array) << "resident memory grew from " << before << " to "
                                       << after << " bytes over 59 ensembles";
}
