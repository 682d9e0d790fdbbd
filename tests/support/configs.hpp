#pragma once
// Config text shared by the C++ tests. The tiny valid config of each model (the one the bad-input
// cases break, and that several tests run as it is) is a file, tests/bad_inputs/base/<model>.yaml,
// read by test::base_config and shared with the fuzzers and the Python tests.

namespace granboltz::test {

/// The dsmc lines, after those that choose the gas, of a short heated run of hard spheres
/// (lambda = 1, GRW05's C = 1/(4 pi)) with every output that has state of its own: the histogram
/// and its components, moments, steady averages. The checkpoint, resume, thread and shard tests of
/// the engines append it to their gas (particles, alpha or a restitution law, the dimension).
inline constexpr const char* kHeatedStatefulOutputs = R"(  beta: 0.125
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 2
  observe_every: 0.5
  histogram: {shells: 12, radius: 5, component: true}
  moments: 16
  steady_from: 0.5
)";

}  // namespace granboltz::test
