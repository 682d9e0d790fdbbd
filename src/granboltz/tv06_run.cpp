// Placeholder until the TV06 simulations land (issue 3): refuses clearly instead of guessing.
#include "granboltz/tv06_run.hpp"

namespace granboltz {

void run_tv06(H5Writer&, const Config& config, const DriverOptions&) {
  throw ConfigError("model: " + model_name(config.model) + " is not available in this build yet");
}

double tv06_memory_estimate(const Config&, unsigned) { return 0.0; }

}  // namespace granboltz
