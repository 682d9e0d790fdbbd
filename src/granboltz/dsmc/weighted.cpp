#include "granboltz/dsmc/weighted.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "granboltz/config/reader.hpp"
#include "granboltz/dsmc/initial_state.hpp"
#include "granboltz/dsmc/particles_io.hpp"
#include "granboltz/physics/collision.hpp"
#include "granboltz/physics/geometry.hpp"
#include "granboltz/physics/heating.hpp"
#include "granboltz/physics/restitution/collide.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz {

namespace {
constexpr std::uint64_t kPauseMask = (1u << 14) - 1;
constexpr std::uint64_t kProgressMask = (1u << 18) - 1;
// The reduction brings the count down to this fraction of N_max: with kappa > 0 a collision adds
// two particles, so a reduction (O(n log n)) runs once per ~N_max/10 collisions.
constexpr double kReduceTo = 0.8;
// No weight falls below this fraction of the initial 1/n (weighted_collide's floor, and the dust
// thinning at every reduction): a collision leaves the lighter partner kappa/(1 + kappa) of its
// weight, and lineages of light particles used to collide on until their weights underflowed
// (1e-308) and the observables turned into NaN. 1e-200 of 1/n is far below any weight a tail
// needs (the papers' tails reach f/f(0) = 1e-40, their lightest particles about 1e-60 of 1/n) and
// below the round-off of every sum over the particles, so what the floor drops or moves is not
// seen.
constexpr double kWeightFloor = 1e-200;
// Gaussian thermostat: the lazy scale is folded into the velocities once s^2 passes this (as in
// the constant-weight engine), besides at every sweep, reduction and observation.
constexpr double kRefold = 0x1p8;

// The weighted centre of a particle set: total weight G, mean velocity V = sum g v / G, and the
// centred energy E = sum g |v - V|^2 (summed in particle order, as every caller did before).
struct WeightedCentre {
  double G = 0.0;
  Vec3 V;
  double E = 0.0;
};

WeightedCentre weighted_centre(std::span<const Particle> p, std::span<const double> g) {
  WeightedCentre c;
  Vec3 M;
  for (std::size_t i = 0; i < p.size(); ++i) c.G += g[i], M += g[i] * p[i].v;
  c.V = (1.0 / c.G) * M;
  for (std::size_t i = 0; i < p.size(); ++i) c.E += g[i] * norm2(p[i].v - c.V);
  return c;
}
}  // namespace

// ---- Sum tree ----

void SumTree::resize(std::size_t capacity) {
  leaves_ = 1;
  while (leaves_ < capacity) leaves_ *= 2;
  node_.assign(2 * leaves_, 0.0);
}

// Inlined into the event loop (GCC stopped doing it by itself once the loop became a template).
GRANBOLTZ_HOT void SumTree::set(std::size_t i, double g) {
  std::size_t k = leaves_ + i;
  node_[k] = g;
  for (k /= 2; k >= 1; k /= 2) node_[k] = node_[2 * k] + node_[2 * k + 1];
}

std::size_t SumTree::find(double x) const {
  std::size_t k = 1;
  while (k < leaves_) {
    const std::size_t left = 2 * k;
    // Round-off may leave x just above a subtree's sum: never enter a subtree of weight 0.
    if (x < node_[left] || node_[left + 1] == 0.0) {
      k = left;
    } else {
      x -= node_[left];
      k = left + 1;
    }
  }
  return k - leaves_;
}

// ---- Kernels ----

WeightedMoments weighted_moments(std::span<const Particle> p, std::span<const double> g) {
  WeightedMoments m;
  for (std::size_t i = 0; i < p.size(); ++i) {
    m.mass += g[i];
    m.momentum += g[i] * p[i].v;
    m.energy += g[i] * norm2(p[i].v);
  }
  return m;
}

Vec3 weighted_heat_flux(std::span<const Particle> p, std::span<const double> g) {
  double G = 0.0;
  Vec3 M;
  for (std::size_t i = 0; i < p.size(); ++i) G += g[i], M += g[i] * p[i].v;
  const Vec3 V = (1.0 / G) * M;
  Vec3 q;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 w = p[i].v - V;
    q += (g[i] * norm2(w)) * w;
  }
  return q;
}

namespace {
// The weights' part of a weighted collision, given the post-collision velocities.
int replace_or_append(Particles& p, std::vector<double>& g, std::size_t a, std::size_t b, Vec3 va,
                      Vec3 vb, double kappa, double t, double floor) {
  // gamma = min(g_a, g_b)/(1 + kappa): for kappa = 0 the lighter partner's remainder is exactly
  // 0 (x - x/1 = x - x), and with equal weights both are replaced: ordinary DSMC.
  double gamma = std::min(g[a], g[b]) / (1.0 + kappa);
  // Below the floor the collision moves the whole lighter weight (as for kappa = 0) and a
  // remainder below it is dropped: no weight ever falls below the floor, so none can underflow.
  // Only particles lighter than (1 + kappa) floor collide otherwise.
  if (gamma < floor) gamma = std::min(g[a], g[b]);
  int appended = 0;
  const std::size_t idx[2] = {a, b};
  const Vec3 post[2] = {va, vb};
  for (int k = 0; k < 2; ++k) {
    const std::size_t i = idx[k];
    const double rest = g[i] - gamma;
    if (rest <= 0.0 || rest < floor) {  // replaced: the slot becomes the new particle
      p[i].v = post[k];
      p[i].t = t;
      g[i] = gamma;
    } else {
      g[i] = rest;
      p.push_back(Particle{post[k], t});
      g.push_back(gamma);
      ++appended;
    }
  }
  return appended;
}
}  // namespace

int weighted_collide(Particles& p, std::vector<double>& g, std::size_t a, std::size_t b, Vec3 e,
                     double alpha, double kappa, double t, double floor) {
  Vec3 va = p[a].v, vb = p[b].v;
  collide(va, vb, e, alpha);
  return replace_or_append(p, g, a, b, va, vb, kappa, t, floor);
}

int weighted_collide(Particles& p, std::vector<double>& g, std::size_t a, std::size_t b, Vec3 e,
                     const RestitutionLaw& law, double kappa, double t, double s2, double floor) {
  if (const auto* k = std::get_if<ConstantRestitution>(&law))
    return weighted_collide(p, g, a, b, e, k->alpha, kappa, t, floor);
  Vec3 va = p[a].v, vb = p[b].v;
  collide_law(va, vb, e, law, s2);
  return replace_or_append(p, g, a, b, va, vb, kappa, t, floor);
}

void merge_group(Particles& p, std::vector<double>& g, std::span<const std::uint32_t> members,
                 Reduction reduction, Vec3 e) {
  double G = 0.0;
  Vec3 M;
  for (std::uint32_t i : members) G += g[i], M += g[i] * p[i].v;
  const Vec3 V = (1.0 / G) * M;
  double E = 0.0;  // mean |w|^2, w = v - V
  Vec3 q;          // mean w |w|^2 (the group's central heat flux per unit mass, times 2)
  for (std::uint32_t i : members) {
    const Vec3 w = p[i].v - V;
    const double w2 = norm2(w);
    E += g[i] * w2;
    q += (g[i] * w2) * w;
  }
  E /= G;
  q = (1.0 / G) * q;
  // Two particles V + a e (weight G p) and V - b e (weight G (1 - p)): a two-point law on the
  // line with mean 0 and variance E for any p, a = sqrt(E (1-p)/p), b = sqrt(E p/(1-p)). Its third
  // moment is E^{3/2} (1 - 2p)/sqrt(p (1-p)); with e = q/|q| it equals |q| when
  // 1 - 2p = x, x = s/sqrt(4 + s^2), s = |q|/E^{3/2} (solve 2x/sqrt(1 - x^2) = s): then the
  // vector heat flux G p a^3 e - G (1-p) b^3 e = G q is kept as well. energy: p = 1/2, e random.
  double pr = 0.5;
  const double qn = norm(q);
  if (reduction == Reduction::kHeatFlux && qn > 0.0 && E > 0.0) {
    const double s = qn / (E * std::sqrt(E));
    const double x = s / std::sqrt(4.0 + s * s);
    pr = 0.5 * (1.0 - x);
    e = (1.0 / qn) * q;
  }
  const double a = std::sqrt(E * (1.0 - pr) / pr), b = std::sqrt(E * pr / (1.0 - pr));
  const std::uint32_t i0 = members[0], i1 = members[1];
  const double t = p[i0].t;  // the caller has kicked every member to the same time
  p[i0] = Particle{V + a * e, t};
  p[i1] = Particle{V - b * e, t};
  g[i0] = G * pr;
  g[i1] = G * (1.0 - pr);
  for (std::size_t k = 2; k < members.size(); ++k) g[members[k]] = 0.0;
}

namespace {
void compact(Particles& p, std::vector<double>& g) {
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (g[i] > 0.0) {
      p[k] = p[i];
      g[k] = g[i];
      ++k;
    }
  p.resize(k);
  g.resize(k);
}
}  // namespace

namespace {
// A unit vector delta with A delta = 0, A the K x (K + 1) matrix whose columns are the rows of
// `at` ((K + 1) x K, row-major, K <= 5), by Gaussian elimination of A with full pivoting: the
// first column without a pivot is set to 1, the pivot columns are solved for by back-substitution
// (a rank below K leaves more free columns, set to 0). Written out rather than a GSL QR: for a
// 5 x 6 matrix the calls into GSL and its BLAS cost about ten times the arithmetic, and a
// reduction runs up to a few thousand of these.
void null_vector(const double* at, std::size_t K, double* delta) {
  const std::size_t m = K + 1;
  double a[5][6];
  for (std::size_t r = 0; r < K; ++r)
    for (std::size_t c = 0; c < m; ++c) a[r][c] = at[c * K + r];
  std::size_t col[6];
  for (std::size_t c = 0; c < m; ++c) col[c] = c;
  double scale = 0.0;
  for (std::size_t r = 0; r < K; ++r)
    for (std::size_t c = 0; c < m; ++c) scale = std::max(scale, std::fabs(a[r][c]));
  std::size_t rank = 0;
  for (; rank < K; ++rank) {
    std::size_t pr = rank, pc = rank;
    double best = 0.0;
    for (std::size_t r = rank; r < K; ++r)
      for (std::size_t c = rank; c < m; ++c)
        if (std::fabs(a[r][c]) > best) best = std::fabs(a[r][c]), pr = r, pc = c;
    if (!(best > 0x1p-40 * scale)) break;  // the rest is round-off: rank found
    if (pr != rank)
      for (std::size_t c = 0; c < m; ++c) std::swap(a[rank][c], a[pr][c]);
    if (pc != rank) {
      for (std::size_t r = 0; r < K; ++r) std::swap(a[r][rank], a[r][pc]);
      std::swap(col[rank], col[pc]);
    }
    for (std::size_t r = rank + 1; r < K; ++r) {
      const double f = a[r][rank] / a[rank][rank];
      for (std::size_t c = rank; c < m; ++c) a[r][c] -= f * a[rank][c];
    }
  }
  double x[6] = {0, 0, 0, 0, 0, 0};
  x[rank] = 1.0;  // the first free column (rank <= K < m)
  for (std::size_t r = rank; r-- > 0;) {
    double sum = a[r][rank];
    for (std::size_t c = r + 1; c < rank; ++c) sum += a[r][c] * x[c];
    x[r] = -sum / a[r][r];
  }
  double norm2 = 0.0;
  for (std::size_t c = 0; c < m; ++c) norm2 += x[c] * x[c];
  const double inv = 1.0 / std::sqrt(norm2);
  for (std::size_t c = 0; c < m; ++c) delta[col[c]] = inv * x[c];
}
}  // namespace

std::size_t thin_step(Particles& p, std::vector<double>& g, std::span<const std::uint32_t> step,
                      int dimension, Engine& eng) {
  // K conserved sums (mass, the d momenta, energy) over m = K + 1 particles leave (at least) one
  // direction delta of weight changes with A delta = 0, A the K x m matrix of 1, v, |v|^2: moving
  // the weights along it keeps those sums for any step lambda, and every other sum
  // sum g f(v) changes by lambda sum delta_i f(v_i). Stepping to the first zero weight in the
  // direction +delta (lambda_+) with probability lambda_-/(lambda_+ + lambda_-), else to the first
  // in -delta (-lambda_-), gives E[lambda] = 0: one particle fewer, the K sums exact, every other
  // sum unchanged in expectation (the "agnostic conservative down-sampling" of Gonoskov, Comput.
  // Phys. Commun. 271 (2022) 108200). No velocity is created or moved, only weights. A particle
  // far lighter than the others of its step goes with probability near 1, and its weight is all
  // that moves.
  const std::size_t K = static_cast<std::size_t>(dimension) + 2, m = K + 1;
  if (step.size() != m) throw std::logic_error("thin_step: needs d + 3 particles");
  // The null space of A is that of any invertible row combination of it: the velocities are
  // centred and scaled on the step, which keeps the elimination well conditioned.
  Vec3 c;
  for (std::uint32_t i : step) c += p[i].v;
  c = (1.0 / static_cast<double>(m)) * c;
  double spread = 0.0;
  for (std::uint32_t i : step) spread += norm2(p[i].v - c);
  const double inv = spread > 0.0 ? std::sqrt(static_cast<double>(m) / spread) : 1.0;
  std::array<double, 6 * 5> at{};  // A transposed: row r = (1, u, |u|^2) of particle r
  for (std::size_t r = 0; r < m; ++r) {
    const Vec3 u = inv * (p[step[r]].v - c);
    double* row = &at[r * K];
    row[0] = 1.0;
    row[1] = u.x;
    row[2] = u.y;
    if (dimension == 3) row[3] = u.z;
    row[K - 1] = norm2(u);
  }
  std::array<double, 6> delta{};
  null_vector(at.data(), K, delta.data());
  double up = std::numeric_limits<double>::infinity(), down = up;
  std::size_t k_up = m, k_down = m;
  for (std::size_t r = 0; r < m; ++r) {
    const double w = g[step[r]];
    if (delta[r] < 0.0 && w / -delta[r] < up) up = w / -delta[r], k_up = r;
    if (delta[r] > 0.0 && w / delta[r] < down) down = w / delta[r], k_down = r;
  }
  if (k_up == m || k_down == m) return 0;  // sum delta = 0: both signs, up to round-off
  const bool go_up = uniform01(eng) * (up + down) < down;
  const double lambda = go_up ? up : -down;
  const std::size_t gone = go_up ? k_up : k_down;
  std::size_t removed = 0;
  for (std::size_t r = 0; r < m; ++r) {
    double& w = g[step[r]];
    const double before = w;
    w = r == gone ? 0.0 : w + lambda * delta[r];
    if (w <= 0x1p-46 * before) w = 0.0, ++removed;  // `gone`, and a tie with it (to round-off)
  }
  return removed;
}

namespace {
// kUnbiased: thinning by thin_step until the count is at most `target`. The particles are binned
// as for the merges; in every cell the candidates are ranked by their share of the cell's
// weight, g_i / W_cell, smallest first over all cells, and each candidate's step takes the d + 2
// lightest others of its cell: the light particles of the crowded cells go first, the tail's
// sparse cells are left alone, and a step's weight goes to the light particles next to it, so
// that they grow towards their neighbours' weights. Only particles up to w_cap = 2 G / target take
// part: the survivors of a thinning gain the removed weight, and without the cap those of many
// reductions grew heavy (measured in the HCS at alpha = 0.6, n = 120, N_max = 360: the
// effective number (sum g)^2 / sum g^2 fell from 120 to 25-35, the heaviest at 10/n). The cap is
// doubled only if one cell of everyone cannot reach the target. Thinning moves weight only within
// a cell, so the ranking stays valid while the cell is thinned.
void thin_particles(Particles& p, std::vector<double>& g, std::size_t target, Engine& eng,
                    int dimension) {
  const std::size_t K = static_cast<std::size_t>(dimension) + 2;
  target = std::max(target, K + 1);
  if (p.size() <= target) return;
  const auto [G, V, E] = weighted_centre(p, g);
  const double h0 = 0.5 * std::sqrt(std::max(E / (static_cast<double>(dimension) * G), 1e-300));
  double h = h0;
  double w_cap = 2.0 * G / static_cast<double>(target);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  struct Candidate {
    double share;
    std::uint32_t cell, index;
  };
  std::vector<Candidate> ranked;
  std::vector<std::pair<std::size_t, std::size_t>> cells;  // (start, length) in `keyed`
  std::vector<std::size_t> alive, first;  // per cell: members left, first one not removed
  std::array<std::uint32_t, 6> step{};
  while (p.size() > target) {
    // Only the particles up to w_cap, keyed by cell and, within a cell, lightest first.
    keyed.clear();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (g[i] > w_cap) continue;
      const Vec3 w = (1.0 / h) * (p[i].v - V);
      auto bin = [](double x) {
        return static_cast<std::uint64_t>(std::floor(std::clamp(x, -0x1p20, 0x1p20 - 1)) + 0x1p20);
      };
      keyed.push_back(
          {(bin(w.x) << 42) | (bin(w.y) << 21) | bin(w.z), static_cast<std::uint32_t>(i)});
    }
    std::sort(keyed.begin(), keyed.end());  // by cell, then index
    cells.clear();
    ranked.clear();
    for (std::size_t s = 0; s < keyed.size();) {
      std::size_t e = s + 1;
      while (e < keyed.size() && keyed[e].first == keyed[s].first) ++e;
      if (e - s >= K + 1) {
        std::stable_sort(keyed.begin() + static_cast<std::ptrdiff_t>(s),
                         keyed.begin() + static_cast<std::ptrdiff_t>(e),
                         [&](const auto& x, const auto& y) { return g[x.second] < g[y.second]; });
        double W = 0.0;
        for (std::size_t k = s; k < e; ++k) W += g[keyed[k].second];
        const auto id = static_cast<std::uint32_t>(cells.size());
        for (std::size_t k = s; k < e; ++k)
          ranked.push_back({g[keyed[k].second] / W, id, keyed[k].second});
        cells.push_back({s, e - s});
      }
      s = e;
    }
    std::sort(ranked.begin(), ranked.end(), [](const Candidate& x, const Candidate& y) {
      return x.share < y.share || (x.share == y.share && x.index < y.index);
    });
    alive.assign(cells.size(), 0);
    first.assign(cells.size(), 0);
    for (std::size_t c = 0; c < cells.size(); ++c)
      alive[c] = cells[c].second, first[c] = cells[c].first;
    std::size_t count = p.size();
    for (const Candidate& x : ranked) {
      if (count <= target) break;
      if (g[x.index] == 0.0 || alive[x.cell] <= K) continue;
      step[0] = x.index;
      std::size_t filled = 1;
      const auto [start, len] = cells[x.cell];
      // The lightest go first, so the cell's removed members gather at its front: skip them once.
      std::size_t& k0 = first[x.cell];
      while (k0 < start + len && g[keyed[k0].second] == 0.0) ++k0;
      for (std::size_t k = k0; k < start + len && filled <= K; ++k) {
        const std::uint32_t j = keyed[k].second;
        if (j != x.index && g[j] > 0.0) step[filled++] = j;
      }
      const std::size_t removed = thin_step(p, g, std::span(step.data(), K + 1), dimension, eng);
      count -= removed;
      alive[x.cell] -= removed;
    }
    compact(p, g);
    h *= 2.0;                                 // not yet enough: coarser cells
    if (h > 64.0 * h0) h = h0, w_cap *= 2.0;  // one cell holds everyone: a higher cap
  }
}
}  // namespace

void reduce_particles(Particles& p, std::vector<double>& g, std::size_t target, Reduction reduction,
                      Engine& eng, int dimension) {
  if (reduction == Reduction::kUnbiased) return thin_particles(p, g, target, eng, dimension);
  target = std::max<std::size_t>(target, 2);
  if (p.size() <= target) return;
  const auto [G, V, E] = weighted_centre(p, g);
  const double h0 = 0.5 * std::sqrt(std::max(E / (static_cast<double>(dimension) * G), 1e-300));
  double h = h0;
  // A merged group weighs at most w_cap = 8 G / target: merging whole crowded cells again and
  // again would concentrate the mass on a few heavy particles (the effective number 1/sum g^2
  // fell to ~15 of 3200 in a Maxwell steady state), and their kicks would make the total momentum
  // random-walk. Relaxed (doubled) only if cells up to 16 sqrt(T) cannot reach the target.
  double w_cap = 8.0 * G / static_cast<double>(target);
  // A cell is 21 bits per axis packed in one word (one comparison per sort step); the clamp at
  // 2^20 cells, beyond 10^5 sqrt(T), is never reached.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  std::vector<std::uint32_t> members, cell;
  while (p.size() > target) {
    keyed.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec3 w = (1.0 / h) * (p[i].v - V);
      auto bin = [](double x) {
        return static_cast<std::uint64_t>(std::floor(std::clamp(x, -0x1p20, 0x1p20 - 1)) + 0x1p20);
      };
      keyed[i] = {(bin(w.x) << 42) | (bin(w.y) << 21) | bin(w.z), static_cast<std::uint32_t>(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    // Cells as runs of equal keys, most crowded first (ties: in key order, deterministic).
    std::vector<std::pair<std::size_t, std::size_t>> cells;  // (start, length)
    for (std::size_t s = 0; s < keyed.size();) {
      std::size_t e = s + 1;
      while (e < keyed.size() && keyed[e].first == keyed[s].first) ++e;
      if (e - s >= 3) cells.push_back({s, e - s});
      s = e;
    }
    std::stable_sort(cells.begin(), cells.end(),
                     [](const auto& x, const auto& y) { return x.second > y.second; });
    std::size_t count = p.size();
    for (const auto& [start, len] : cells) {
      if (count <= target) break;
      // Within a cell, lightest first, in consecutive groups of weight <= w_cap.
      cell.clear();
      for (std::size_t k = start; k < start + len; ++k) cell.push_back(keyed[k].second);
      std::sort(cell.begin(), cell.end(), [&](std::uint32_t x, std::uint32_t y) {
        return g[x] < g[y] || (g[x] == g[y] && x < y);
      });
      members.clear();
      double w = 0.0;
      for (std::size_t k = 0; k <= cell.size() && count > target; ++k) {
        if (k < cell.size() && w + g[cell[k]] <= w_cap) {
          members.push_back(cell[k]);
          w += g[cell[k]];
          continue;
        }
        if (members.size() >= 3) {
          // The direction of an energy merge: isotropic in the velocity space (the plane in d = 2).
          merge_group(p, g, members, reduction,
                      dimension == 2 ? unit_circle(eng) : unit_vector(eng));
          count -= members.size() - 2;
        }
        members.clear();
        w = 0.0;
        if (k < cell.size() && g[cell[k]] <= w_cap) members.push_back(cell[k]), w = g[cell[k]];
      }
    }
    compact(p, g);
    h *= 2.0;  // not yet enough: coarser cells
    if (h > 64.0 * h0) h = h0, w_cap *= 2.0;
  }
}

// ---- Importance splitting ----

namespace {
// A particle far beyond its target would become thousands of copies at once; 16 per sweep is
// enough when a sweep's kicks move a particle by about one e-fold of the target weight.
constexpr double kMaxCopies = 16.0;
}  // namespace

double split_target(const SplitSpec& s, double g_ref, double r) {
  if (r <= s.radius) return g_ref;
  // Frozen beyond max_radius: particles there are no longer split, and their number decays with
  // the tail instead of crowding a region nobody observes.
  r = std::min(r, s.max_radius);
  // (r/r_s)^2: a shell's volume grows as r^2, so that with exp(-rate r^power) near the true tail
  // every shell of the tail holds about as many particles as the first.
  const double x = r / s.radius;
  return g_ref * x * x * std::exp(-s.rate * (std::pow(r, s.power) - std::pow(s.radius, s.power)));
}

SplitCounts split_particles(Particles& p, std::vector<double>& g, Vec3 V, const SplitSpec& s,
                            double g_ref, Engine& eng, double scale) {
  SplitCounts out;
  std::vector<std::pair<std::int64_t, std::uint32_t>> light;  // (band, index)
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double r = norm(p[i].v - V);
    if (r <= s.radius) continue;
    ++out.tail;
    // Never above g_ref: roulette must not build particles heavier than the bulk's, whose
    // noise (the SWPM's O(1/n_eff) bias) would reach every moment.
    const double target = std::min(scale * split_target(s, g_ref, r), g_ref);
    if (g[i] > 2.0 * target) {
      const double k = std::min(std::floor(g[i] / target), kMaxCopies);
      const double each = g[i] / k;
      const auto copies = static_cast<std::size_t>(k) - 1;
      for (std::size_t c = 0; c < copies; ++c) {
        p.push_back(p[i]);
        g.push_back(each);
      }
      g[i] -= static_cast<double>(copies) * each;  // the sum stays g[i] to round-off
      out.copies += copies;
      out.tail += copies;
    } else if (g[i] < 0.25 * target) {
      light.push_back({static_cast<std::int64_t>(std::floor(std::log(g_ref / target))),
                       static_cast<std::uint32_t>(i)});
    }
  }
  std::sort(light.begin(), light.end());
  for (std::size_t k = 0; k + 1 < light.size(); k += 2) {
    if (light[k].first != light[k + 1].first) {  // alone in its band: waits for the next sweep
      --k;
      continue;
    }
    const std::uint32_t a = light[k].second, b = light[k + 1].second;
    const double sum = g[a] + g[b];
    const bool keep_a = uniform01(eng) * sum < g[a];
    g[keep_a ? a : b] = sum;
    g[keep_a ? b : a] = 0.0;
    ++out.removed;
    --out.tail;
  }
  if (out.removed) compact(p, g);
  return out;
}

// ---- The weighted ensemble ----

WeightedEnsemble::WeightedEnsemble(const DsmcConfig& config, std::uint64_t seed,
                                   std::uint64_t ensemble, ProgressSlot* progress)
    : c_(config),
      p_(config.particles),
      g_(config.particles, 1.0 / static_cast<double>(config.particles)),
      // The Gaussian thermostat keeps the strict bound 2 |v - V| >= |v - w| between folds, so the
      // majorant recomputed at every fold can shrink with the cooling and stay a bound.
      adapt_factor2_(config.majorant_update == MajorantUpdate::kStrict ||
                             config.thermostat == Thermostat::kGaussian
                         ? 4.0
                         : 1.0),
      heated_(config.thermostat == Thermostat::kWhiteNoise && config.beta > 0.0),
      gaussian_(config.thermostat == Thermostat::kGaussian),
      floor_(kWeightFloor / static_cast<double>(config.particles)),
      events_(make_stream(seed, ensemble, Consumer::kEvents)),
      pairs_(make_stream(seed, ensemble, Consumer::kPairs)),
      sweep_(make_stream(seed, ensemble, Consumer::kSweep)),
      reduce_(make_stream(seed, ensemble, Consumer::kReduce)),
      split_(make_stream(seed, ensemble, Consumer::kSplit)),
      progress_(progress) {
  Engine init = make_stream(seed, ensemble, Consumer::kInitial);
  const double sd = std::sqrt(c_.initial_temperature);
  const PreparedStart start = prepared_start(c_.initial_temperature_tensor, c_.initial_heat_flux,
                                             c_.dimension, c_.initial_temperature);
  Vec3 sum;
  for (auto& q : p_) {
    if (const auto v = start.velocity(1.0, init)) {
      q.v = *v;
    } else if (c_.dimension == 2) {  // the same draws as the constant-weight engine's
      const double x = normal(init);
      const double y = normal(init);
      q.v = {sd * x, sd * y, 0.0};
    } else {
      q.v = sd * normal3(init);
    }
    q.t = 0.0;
    sum += q.v;
  }
  v0_ = (1.0 / static_cast<double>(p_.size())) * sum;
  if (gaussian_) fold_scale();  // the thermostat holds T at T0 exactly, from t = 0 on
  double r2 = 0.0;
  for (const auto& q : p_) r2 = std::max(r2, norm2(q.v - v0_));
  u_max_ = 2.0 * std::sqrt(r2);
  rebuild_tree();
}

void WeightedEnsemble::set_velocities(const std::vector<Vec3>& v) {
  Vec3 sum;
  double G = 0.0;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    p_[i].v = v[i];
    p_[i].t = t_;
    sum += g_[i] * v[i];
    G += g_[i];
  }
  v0_ = (1.0 / G) * sum;
  if (gaussian_) fold_scale();
  recompute_majorant();
}

void WeightedEnsemble::fold_scale() {
  // The weighted sums: the weighted centred temperature sum g |v - V|^2 / (d sum g) is T0 to
  // round-off, and the bulk velocity is back on the conserved V after the roulette's momentum
  // noise (it keeps momentum only in expectation). The collisions' scale s^2 is added to the
  // cooling integral first: it is the factor by which the collisions alone (not the roulette or
  // the round-off, which the fold absorbs too) cooled the gas.
  const auto folded = GaussianThermostat::fold(
      std::span<Particle>(p_.data(), p_.size()), {}, v0_,
      [&](double G) {
        return GaussianThermostat::target_of(c_.dimension, G, c_.initial_temperature);
      },
      [&](auto fn) {
        for (std::size_t i = 0; i < p_.size(); ++i) fn(i, g_[i], 0.0);
      });
  cooled_ += std::log(gauss_.s2);
  gauss_.set(folded.energy, folded.energy);
}

void WeightedEnsemble::recompute_majorant() {
  // Right after a fold the stored velocities are the true ones: 2 max |v - V| bounds every
  // relative speed, and it follows the cooled gas down instead of only growing.
  if (c_.kernel.lambda == 0.0) return;
  double r2 = 0.0;
  for (const auto& q : p_) r2 = std::max(r2, norm2(q.v - v0_));
  u_max_ = 2.0 * std::sqrt(r2);
}

void WeightedEnsemble::rebuild_tree() {
  // At most N_max + 2 particles: a collision adds two, and a reduction follows at once.
  p_.reserve(c_.weights.max_particles + 2);
  g_.reserve(c_.weights.max_particles + 2);
  tree_.resize(c_.weights.max_particles + 2);
  for (std::size_t i = 0; i < g_.size(); ++i) tree_.set(i, g_[i]);
}

// Inlined into the event loop, as SumTree::set.
GRANBOLTZ_HOT void WeightedEnsemble::adapt_majorant(const Vec3& v) {
  const double r2 = adapt_factor2_ * norm2(v - v0_);
  if (r2 > u_max_ * u_max_) u_max_ = std::sqrt(r2);
}

void WeightedEnsemble::kick_all_to(double s) {
  if (heated_) {
    for (auto& q : p_) {
      q.v = c_.dimension == 2 ? white_noise_kick_2d(q.v, c_.beta, s - q.t, sweep_)
                              : white_noise_kick(q.v, c_.beta, s - q.t, sweep_);
      q.t = s;
    }
    counts_.kicks += p_.size();
    if (c_.kernel.lambda != 0.0)
      for (const auto& q : p_) adapt_majorant(q.v);
  } else {
    if (gaussian_) {  // the true velocities at s
      fold_scale();
      recompute_majorant();
    }
    for (auto& q : p_) q.t = s;
  }
}

void WeightedEnsemble::reduce_to_cap() {
  if (p_.size() <= c_.weights.max_particles) return;
  kick_all_to(t_);  // a group is merged at one time
  thin_dust();
  reduce_particles(
      p_, g_, static_cast<std::size_t>(kReduceTo * static_cast<double>(c_.weights.max_particles)),
      c_.weights.reduction, reduce_, c_.dimension);
  ++reductions_;
  if (gaussian_) {  // the merges keep the energy; the fold makes its sums exact again
    fold_scale();
    recompute_majorant();
  }
}

void WeightedEnsemble::thin_dust() {
  // Dust: a particle lighter than its threshold, floor_ or, for the unbiased reduction,
  // min_weight times the target weight of its place (1/n; with splitting w*(r), as the split
  // sweep's). Without this, the light particles that collisions keep making (each one makes two
  // more) end up holding most of the slots and, in the tail, most of the events: measured in the
  // HCS at alpha = 0.6, n = 120, N_max = 360, 290 of 330 particles weighed below 1e-20/n at speeds
  // 6-38 sqrt(T) and the events per unit time grew without bound. A dust particle is removed by
  // thin_step with the d + 2 heaviest particles as partners: exact mass, momentum and energy,
  // every other moment in expectation, and what moves is the dust's weight, below the threshold.
  const double g_ref = 1.0 / static_cast<double>(c_.particles);
  const bool relative = c_.weights.reduction == Reduction::kUnbiased;
  const SplitSpec& sp = c_.weights.split;
  auto threshold = [&](const Particle& q) {
    if (!relative) return floor_;
    const double target =
        sp.on ? std::min(split_scale_ * split_target(sp, g_ref, norm(q.v - v0_)), g_ref) : g_ref;
    return std::max(floor_, c_.weights.min_weight * target);
  };
  // Every threshold is at most max(floor_, min_weight / n): only lighter particles need w*(r).
  const double ceiling = relative ? std::max(floor_, c_.weights.min_weight * g_ref) : floor_;
  std::vector<std::uint32_t> dust;
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (g_[i] < ceiling && g_[i] < threshold(p_[i])) dust.push_back(static_cast<std::uint32_t>(i));
  if (dust.empty()) return;
  const std::size_t K = static_cast<std::size_t>(c_.dimension) + 2;
  if (p_.size() - dust.size() < K) return;  // nothing to move it to (a near-empty system)
  std::vector<std::uint32_t> heavy(p_.size());
  std::array<std::uint32_t, 6> step{};
  auto pick_partners = [&] {  // the K heaviest (ties by index)
    heavy.resize(p_.size());
    for (std::size_t i = 0; i < p_.size(); ++i) heavy[i] = static_cast<std::uint32_t>(i);
    std::partial_sort(heavy.begin(), heavy.begin() + static_cast<std::ptrdiff_t>(K), heavy.end(),
                      [&](std::uint32_t x, std::uint32_t y) {
                        return g_[x] > g_[y] || (g_[x] == g_[y] && x < y);
                      });
    for (std::size_t k = 0; k < K; ++k) step[k + 1] = heavy[k];
  };
  pick_partners();
  for (std::uint32_t d : dust) {
    if (g_[d] == 0.0) continue;
    bool fresh = true;
    for (std::size_t k = 1; k <= K; ++k) fresh = fresh && g_[step[k]] > 0.0 && step[k] != d;
    if (!fresh) pick_partners();
    step[0] = d;
    thin_step(p_, g_, std::span(step.data(), K + 1), c_.dimension, reduce_);
  }
  compact(p_, g_);
}

void WeightedEnsemble::split_sweep() {
  // Kicking everyone to t_ does not change the law (Gaussian kicks compose); it gives every
  // particle its current velocity, so the decision follows the diffusion path.
  kick_all_to(t_);
  const double g_ref = 1.0 / static_cast<double>(c_.particles);
  SplitCounts c = split_particles(p_, g_, v0_, c_.weights.split, g_ref, split_, split_scale_);
  ++splits_;
  // Population control by roulette, which is unbiased: an importance function steeper than the
  // true tail would crowd it, the reduction would then merge the bulk into a few heavy particles
  // (biasing everything by O(1/n_eff)) and tail particles in coarse cells. Raising the tail's
  // targets until it holds at most half of N_max thins it at once; they relax when it is sparse.
  const double cap = static_cast<double>(c_.weights.max_particles);
  while (static_cast<double>(c.tail) > 0.5 * cap && split_scale_ < 0x1p60) {
    split_scale_ *= 2.0;
    c = split_particles(p_, g_, v0_, c_.weights.split, g_ref, split_, split_scale_);
  }
  if (static_cast<double>(c.tail) < 0.125 * cap && split_scale_ > 1.0) split_scale_ *= 0.5;
  if (gaussian_) {  // the roulette changed the energy (in expectation it kept it)
    fold_scale();
    recompute_majorant();
  }
  reduce_to_cap();
  rebuild_tree();
  if (c_.kernel.lambda != 0.0)
    for (const auto& q : p_) adapt_majorant(q.v);
}

bool WeightedEnsemble::advance_to(double s, const std::atomic<bool>* pause) {
  // The geometry (physics/geometry.hpp) at compile time, as in the constant-weight loops.
  if (c_.dimension == 3) return advance_with<Sphere3>(s, pause);
  if (c_.geometry == Geometry::kImpact) return advance_with<CircleImpact>(s, pause);
  return advance_with<CircleUniform>(s, pause);
}

template <class Geo>
bool WeightedEnsemble::advance_with(double s, const std::atomic<bool>* pause) {
  const double alpha = c_.alpha, beta = c_.beta, kappa = c_.weights.kappa;
  const bool constant_law = is_constant(c_.restitution);
  const bool maxwell = c_.kernel.lambda == 0.0;
  const double K = c_.kernel.area * c_.kernel.gamma * c_.kernel.C * (1.0 + kappa);  // 4 pi in d = 3
  std::uint64_t events = 0;
  for (;;) {
    if (pause && (events & kPauseMask) == 0 && pause->load(std::memory_order_relaxed)) return false;
    // Majorant process: the ordered pair (i, j), i != j, is proposed at rate
    // (1 + kappa) K_B U^lambda g_i, K_B = 4 pi gamma C (i by weight from the sum tree, j uniform
    // among the n - 1 others), so the unordered pair at rate (1 + kappa) K_B U^lambda (g_i + g_j)
    // >= (1 + kappa) max(g_i, g_j) B(|u|), B = K_B |u|^lambda. It is a real collision with
    // probability  max(g_i, g_j)/(g_i + g_j) * min(1, (|u|/U)^lambda)  (the truncated kernel,
    // RW05 eq. 19, as in the constant-weight scheme): the real rate is (1 + kappa) max(g_i, g_j) B.
    const double n = static_cast<double>(p_.size()), G = tree_.total();
    // Gaussian: u_max_ bounds the stored relative speeds, the true ones are s times them; s only
    // changes at collisions, so between events the rate is constant.
    const double rate =
        K * c_.kernel.power(gaussian_ ? std::sqrt(gauss_.s2) * u_max_ : u_max_) * (n - 1.0) * G;
    const double tau = exponential(events_) / rate;
    if (c_.weights.split.on) {
      // A sweep changes n and so the rate: the waiting time is drawn afresh after it (the
      // majorant process is memoryless).
      const double next = static_cast<double>(splits_ + 1) * c_.weights.split.interval;
      if (next < s && t_ + tau >= next) {
        t_ = next;
        split_sweep();
        continue;
      }
    }
    if (t_ + tau >= s) break;
    t_ += tau;
    const std::size_t i = tree_.find(uniform01(pairs_) * G);
    std::size_t j = uniform_index(pairs_, p_.size() - 1);
    if (j >= i) ++j;
    Particle& a = p_[i];
    Particle& b = p_[j];
    if (heated_) {
      white_noise_kick2<Geo::kDim>(a.v, t_ - a.t, b.v, t_ - b.t, beta, events_);
      a.t = b.t = t_;
      counts_.kicks += 2;
      if (!maxwell) adapt_majorant(a.v), adapt_majorant(b.v);
    }
    const double gi = g_[i], gj = g_[j];
    const double accept = std::max(gi, gj) / (gi + gj) *
                          (maxwell ? 1.0 : c_.kernel.acceptance(norm(a.v - b.v), u_max_));
    if (uniform01(events_) < accept) {
      const std::size_t before = p_.size();
      double e_before = 0.0;
      if (gaussian_) e_before = gi * norm2(a.v - v0_) + gj * norm2(b.v - v0_);
      if (constant_law) [[likely]]
        weighted_collide(p_, g_, i, j, Geo::direction(a.v - b.v, events_), alpha, kappa, t_,
                         floor_);
      else
        weighted_collide(p_, g_, i, j, Geo::direction(a.v - b.v, events_), c_.restitution, kappa,
                         t_, gaussian_ ? gauss_.s2 : 1.0, floor_);
      if (gaussian_) {
        // The change of sum g |w - V|^2: the partners' slots and the appended particles.
        double e_after = g_[i] * norm2(p_[i].v - v0_) + g_[j] * norm2(p_[j].v - v0_);
        for (std::size_t k = before; k < p_.size(); ++k) e_after += g_[k] * norm2(p_[k].v - v0_);
        gauss_.after_collision(e_after - e_before);
      }
      tree_.set(i, g_[i]);
      tree_.set(j, g_[j]);
      for (std::size_t k = before; k < p_.size(); ++k) tree_.set(k, g_[k]);
      if (!maxwell) {
        adapt_majorant(p_[i].v), adapt_majorant(p_[j].v);
        for (std::size_t k = before; k < p_.size(); ++k) adapt_majorant(p_[k].v);
      }
      ++counts_.collisions;
      if (p_.size() > c_.weights.max_particles) {
        reduce_to_cap();
        rebuild_tree();
        if (!maxwell)
          for (const auto& q : p_) adapt_majorant(q.v);
      }
      if (gaussian_ && gauss_.s2 > kRefold) {
        fold_scale();
        recompute_majorant();
      }
    } else {
      ++counts_.fictitious;
    }
    if ((++events & kProgressMask) == 0 && progress_)
      progress_->store(t_ / c_.t_end, std::memory_order_relaxed);
  }
  kick_all_to(s);
  t_ = s;
  if (progress_) progress_->store(t_ / c_.t_end, std::memory_order_relaxed);
  return true;
}

// ---- Checkpoints ----

// The whole state, declared once for writing and reading (record/state_archive.hpp), in the
// layout of the checkpoints written so far.
void WeightedEnsemble::visit_state(StateArchive& a) {
  const std::size_t max = c_.weights.max_particles;
  visit_particles(a, "weighted_particles", p_, &g_, c_.dimension,
                  counts_between(2, max, "weights.max_particles"));
  const std::size_t n = p_.size();
  a.pack("scalars", real("t", t_, within(0.0, c_.t_end, "t_end")), real("V_x", v0_.x),
         real("V_y", v0_.y), real("V_z", v0_.z, zero_if(c_.dimension == 2, "in dimension 2")),
         real("u_max", u_max_, at_least(0.0)), real("split scale", split_scale_, at_least(0.0)));
  a.each(
      "weighted_particles", n, 3, [&](std::size_t i) { return p_[i].t; }, within(0.0, t_, "t"));
  a.stream("events_stream", events_);
  a.stream("pairs_stream", pairs_);
  a.stream("sweep_stream", sweep_);
  a.stream("reduce_stream", reduce_);
  a.stream("split_stream", split_);
  a.pack("counters", word("collisions", counts_.collisions), word("fictitious", counts_.fictitious),
         word("kicks", counts_.kicks), word("reductions", reductions_), word("splits", splits_));
  if (gaussian_)  // the lazy scale: the particles above are the stored velocities w
    a.pack("thermostat", real("energy", gauss_.energy, positive()),
           real("target", gauss_.target, positive()), real("cooled", cooled_),
           real("mark cooled", mark_cooled_), real("mark time", mark_time_, within(0.0, t_, "t")));
}

WeightedEnsemble::WeightedEnsemble(const DsmcConfig& config, const H5Reader& in,
                                   const std::string& g, ProgressSlot* progress)
    : c_(config),
      // The Gaussian thermostat keeps the strict bound 2 |v - V| >= |v - w| between folds, so the
      // majorant recomputed at every fold can shrink with the cooling and stay a bound.
      adapt_factor2_(config.majorant_update == MajorantUpdate::kStrict ||
                             config.thermostat == Thermostat::kGaussian
                         ? 4.0
                         : 1.0),
      heated_(config.thermostat == Thermostat::kWhiteNoise && config.beta > 0.0),
      gaussian_(config.thermostat == Thermostat::kGaussian),
      floor_(kWeightFloor / static_cast<double>(config.particles)),
      progress_(progress) {
  StateArchive r(in, g);
  visit_state(r);
  if (gaussian_) gauss_.set(gauss_.energy, gauss_.target);
  rebuild_tree();
}

// ---- Observers ----

Observation measure_weighted(std::span<const Particle> p, std::span<const double> g,
                             std::span<double> moments, int dimension) {
  if (moments.size() > static_cast<std::size_t>(kMaxMoments))
    throw std::logic_error("measure_weighted: more than kMaxMoments speed moments");
  const std::size_t P = moments.size();
  double rho = 0.0;
  Vec3 m;
  for (std::size_t i = 0; i < p.size(); ++i) rho += g[i], m += g[i] * p[i].v;
  const Vec3 V = (1.0 / rho) * m;
  double cc[6] = {0, 0, 0, 0, 0, 0};
  double flux[3] = {0, 0, 0};
  double c4 = 0.0;
  double c2p[kMaxMoments] = {};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 c = p[i].v - V;
    const double w = g[i], c2 = norm2(c);
    cc[0] += w * c.x * c.x;
    cc[1] += w * c.y * c.y;
    cc[2] += w * c.z * c.z;
    cc[3] += w * c.x * c.y;
    cc[4] += w * c.x * c.z;
    cc[5] += w * c.y * c.z;
    flux[0] += w * c.x * c2;
    flux[1] += w * c.y * c2;
    flux[2] += w * c.z * c2;
    c4 += w * c2 * c2;
    double power = 1.0;
    for (std::size_t k = 0; k < P; ++k) {
      power *= c2;
      c2p[k] += w * power;
    }
  }
  // Integrals of the measure sum g delta_v (rho = 1 to round-off), as for constant weights.
  for (std::size_t k = 0; k < P; ++k) moments[k] = c2p[k];
  Observation o{};
  o[0] = rho;
  o[1] = V.x;
  o[2] = V.y;
  o[3] = V.z;
  double* Pm = &o[5];
  Pm[0] = cc[0];
  Pm[4] = cc[1];
  Pm[8] = cc[2];
  Pm[1] = Pm[3] = cc[3];
  Pm[2] = Pm[6] = cc[4];
  Pm[5] = Pm[7] = cc[5];
  const double d = static_cast<double>(dimension);
  const double T = (Pm[0] + Pm[4] + Pm[8]) / (d * rho);
  o[4] = T;
  for (int a = 0; a < 3; ++a) o[14 + a] = 0.5 * flux[a];
  o[17] = c4 - d * (d + 2.0) * T * T;
  o[18] = crit(T, Pm, &o[14], o[17], dimension);
  o[19] = T + norm2(V) / d;
  return o;
}

void radial_histogram_weighted(std::span<const Particle> p, std::span<const double> g,
                               const HistogramSpec& spec, Vec3 V, double* weight,
                               std::uint64_t* count) {
  const std::uint64_t K = spec.shells;
  const double scale = static_cast<double>(K) / spec.radius;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double k = std::floor((spec.bulk ? norm(p[i].v - V) : norm(p[i].v)) * scale);
    const std::uint64_t s = k < static_cast<double>(K) ? static_cast<std::uint64_t>(k) : K;
    weight[s] += g[i];
    ++count[s];
  }
}

void component_histogram_weighted(std::span<const Particle> p, std::span<const double> g,
                                  const HistogramSpec& spec, Vec3 V, double* weight,
                                  std::uint64_t* count) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::uint64_t k = component_bin(p[i].v.x - V.x, spec);
    weight[k] += g[i];
    ++count[k];
  }
}

}  // namespace granboltz
