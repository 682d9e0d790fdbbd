#pragma once
// The thermostats' names as a config value (dsmc.thermostat). A thermostat is one header in
// this folder (its struct: kId, kName, kKicks, kLazyScale and its hooks) plus one enumerator
// here and one entry in ThermostatList (list.hpp).
namespace granboltz {

/// white_noise: heating by white noise of strength beta (the papers; beta = 0 is free cooling);
/// gaussian: all peculiar velocities rescaled so that T stays T0 (the homogeneous cooling state in
/// scaled variables); none: free cooling.
enum class Thermostat { kWhiteNoise, kGaussian, kNone };

}  // namespace granboltz
