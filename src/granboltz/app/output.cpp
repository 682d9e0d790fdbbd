#include "granboltz/app/output.hpp"

#include "granboltz/core/version.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/tv06/run.hpp"

namespace granboltz {

Record layout_of(const Config& config) {
  return config.model == Model::kDsmc ? dsmc_layout(config) : tv06_layout(config);
}

void write_output(H5Writer& out, const Config& config, const Record& record,
                  const std::map<std::string, std::string>& provenance) {
  if (config.model == Model::kDsmc)
    present_dsmc(out, config, record);
  else
    present_tv06(out, config, record);
  record.write(out);
  out.attr("/", "config", config.to_yaml(true));
  out.attr("/", "model", model_name(config.model));
  out.attr("/", "seed", config.seed);
  out.attr("/", "ensembles", config.ensembles);
  out.attr("/", "version", std::string(kVersion));
  out.attr("/", "git_sha", std::string(kGitSha));
  out.group("/provenance");
  for (const auto& [key, value] : provenance) out.attr("/provenance", key, value);
  if (config.model == Model::kDsmc)  // the majorant used, also when `auto` chose it
    out.attr("/provenance", "majorant", std::string(majorant_name(config.dsmc.majorant)));
  // Last, over every dataset: what `granboltz verify` and merge check beyond Fletcher32.
  out.attr("/", "digest", out.digest());
}

Config config_of_file(const H5Reader& in) {
  if (!in.has_attr("/", "config") || !in.exists("/accumulators"))
    throw ConfigError(in.path() + ": not a granboltz output (no config attribute or accumulators)");
  return parse_config(in.attr_string("/", "config"), in.path() + " (stored config)");
}

}  // namespace granboltz
