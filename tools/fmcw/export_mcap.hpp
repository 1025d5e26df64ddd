#pragma once
// fmcw export INPUT -o FILE.mcap --to mcap: a dataset, a `fmcw process` output folder or any
// frames as one MCAP file (io/mcap_export.hpp).

#include <string>

#include "input_flags.hpp"

namespace fmcw::cli {

struct McapExportArgs {
  std::string compression = "zstd";
  std::string topic = "/points";
};

int run_export_mcap(const InputFlags& flags, const std::string& output, const McapExportArgs& args);

}  // namespace fmcw::cli
