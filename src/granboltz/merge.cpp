#include "granboltz/merge.hpp"

#include "granboltz/config_reader.hpp"

namespace granboltz {

void merge_outputs(const std::vector<std::string>&, const std::string&) {
  throw ConfigError("merge is not available in this build yet");
}

}  // namespace granboltz
