#pragma once
// The parts every output file shares: the model's record and datasets, and the attributes that
// make the file explain itself. Used by run, checkpoint and merge alike.
#include <map>
#include <string>

#include "granboltz/app/config.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/record/record.hpp"

namespace granboltz {

/// The empty record of a run of this config (its layout).
Record layout_of(const Config& config);

/// Writes the user-facing datasets, the record and the root attributes (config, model, seed,
/// ensembles, version, git_sha); then `provenance` as attributes of /provenance.
void write_output(H5Writer& out, const Config& config, const Record& record,
                  const std::map<std::string, std::string>& provenance);

/// Reads the config stored in a granboltz output or checkpoint; throws ConfigError naming the
/// file if it is not one.
Config config_of_file(const H5Reader& in);

}  // namespace granboltz
