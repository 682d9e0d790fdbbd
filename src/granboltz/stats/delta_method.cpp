#include "granboltz/stats/delta_method.hpp"

#include <algorithm>

namespace granboltz {

RatioStats ratio_of_means(double mean_x, double mean_y, const Moments2& x, const Moments2& y,
                          const Moments2& xy, std::uint64_t N, bool sample_covariance) {
  const double n = static_cast<double>(N);
  const double mx = x.sum.value() / n, my = y.sum.value() / n;
  const double scale = sample_covariance ? n / (n - 1.0) : 1.0;
  const double vx = std::max(0.0, x.sum_sq.value() / n - mx * mx) * scale;
  const double vy = std::max(0.0, y.sum_sq.value() / n - my * my) * scale;
  const double cxy = (xy.sum.value() / n - mx * my) * scale;
  RatioStats r;
  r.mean = mean_x / mean_y;
  const double my2n = mean_y * mean_y * n;
  r.variance = std::max(0.0, (vx - 2.0 * r.mean * cxy + r.mean * r.mean * vy) / my2n);
  r.bias = (r.mean * vy - cxy) / my2n;
  return r;
}

void add_cross(Moments2* out, const double* M, std::uint64_t P) {
  if (P < 2) return;
  out[0].sum.add(M[0] * M[1]);
  if (P < 3) return;
  out[1].sum.add(M[0] * M[2]);
  out[2].sum.add(M[1] * M[2]);
}

Sonine sonine(const Moments2* M, const Moments2* cross, std::uint64_t P, std::uint64_t N,
              bool sample_covariance, int dimension) {
  Sonine r;
  const double n = static_cast<double>(N);
  const int q = P >= 3 ? 3 : 2;
  double mu[3] = {0, 0, 0}, cov[3][3] = {};
  for (int i = 0; i < q; ++i) mu[i] = M[i].sum.value() / n;
  auto second = [&](int i, int j) {
    if (i == j) return M[i].sum_sq.value();
    const int pair = i + j - 1;  // (0,1) -> 0, (0,2) -> 1, (1,2) -> 2
    return cross[pair].sum.value();
  };
  // Population covariance for the time series (as their variance and ci), sample covariance for
  // the steady averages (as the ensembles estimator of /steady).
  const double denom = sample_covariance ? n - 1 : n;
  for (int i = 0; i < q; ++i)
    for (int j = 0; j < q; ++j) cov[i][j] = (second(i, j) - n * mu[i] * mu[j]) / denom;
  auto variance = [&](const double* g) {
    double v = 0.0;
    for (int i = 0; i < q; ++i)
      for (int j = 0; j < q; ++j) v += g[i] * cov[i][j] * g[j];
    return std::max(0.0, v / n);
  };
  auto bias = [&](const double(&H)[3][3]) {
    double b = 0.0;
    for (int i = 0; i < q; ++i)
      for (int j = 0; j < q; ++j) b += H[i][j] * cov[i][j];
    return 0.5 * b / n;
  };
  const bool plane = dimension == 2;
  const double c2 = plane ? 2.0 / 4.0 : 3.0 / 5.0, c3 = plane ? 4.0 / 24.0 : 9.0 / 35.0;
  const double m2 = mu[0], m4 = mu[1], m6 = mu[2];
  r.a2 = c2 * m4 / (m2 * m2) - 1.0;
  const double g2[3] = {-2.0 * c2 * m4 / (m2 * m2 * m2), c2 / (m2 * m2), 0.0};
  r.var_a2 = variance(g2);
  const double m2_3 = m2 * m2 * m2, m2_4 = m2_3 * m2;
  const double H2[3][3] = {
      {6.0 * c2 * m4 / m2_4, -2.0 * c2 / m2_3, 0.0}, {-2.0 * c2 / m2_3, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  r.bias_a2 = bias(H2);
  if (q == 3) {
    r.a3 = 1.0 + 3.0 * r.a2 - c3 * m6 / (m2 * m2 * m2);
    const double g3[3] = {3.0 * g2[0] + 3.0 * c3 * m6 / (m2 * m2 * m2 * m2), 3.0 * g2[1],
                          -c3 / (m2 * m2 * m2)};
    r.var_a3 = variance(g3);
    const double H3[3][3] = {
        {3.0 * H2[0][0] - 12.0 * c3 * m6 / (m2_4 * m2), 3.0 * H2[0][1], 3.0 * c3 / m2_4},
        {3.0 * H2[1][0], 0.0, 0.0},
        {3.0 * c3 / m2_4, 0.0, 0.0}};
    r.bias_a3 = bias(H3);
  }
  return r;
}

}  // namespace granboltz
