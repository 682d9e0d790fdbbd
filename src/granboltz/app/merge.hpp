#pragma once
// Merging the outputs of the shards of one run.
#include <string>
#include <vector>

namespace granboltz {

/// Merges shard outputs into `output`, identical to the unsharded run in every dataset.
void merge_outputs(const std::vector<std::string>& inputs, const std::string& output);

}  // namespace granboltz
