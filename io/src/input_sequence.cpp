#include "fmcw/io/input_sequence.hpp"

#include <cstdio>
#include <filesystem>

#include "fmcw/core/check.hpp"

namespace fmcw::io {

InputSequence::InputSequence(const std::string& input, const InputOptions& options)
    : options_(options), files_(list_input_files(input, options.format)) {
  for (std::size_t f = 0; f < files_.size(); ++f) {
    if (!is_mcap()) {
      entries_.push_back({f, 0});
      continue;
    }
    mcap_.push_back(std::make_unique<McapFrames>(files_[f], options.mcap));
    for (std::size_t m = 0; m < mcap_.back()->size(); ++m) entries_.push_back({f, m});
  }
}

InputSequence::~InputSequence() = default;

std::string InputSequence::source(std::size_t k) const {
  const Entry& e = entries_.at(k);
  return is_mcap() ? mcap_[e.file]->source(e.message) : files_[e.file];
}

std::string InputSequence::stem(std::size_t k) const {
  const Entry& e = entries_.at(k);
  std::string stem = std::filesystem::path(files_[e.file]).stem().string();
  if (!is_mcap()) return stem;
  char index[24];
  std::snprintf(index, sizeof index, "_%06zu", e.message);
  return stem + index;
}

PcdCloud InputSequence::mcap_cloud(std::size_t k) {
  FMCW_CHECK_ARG(is_mcap(), "InputSequence: not an MCAP input");
  const Entry& e = entries_.at(k);
  return mcap_[e.file]->cloud(e.message);
}

InputFrame InputSequence::read(std::size_t k) {
  if (!is_mcap()) return read_input_frame(files_[entries_.at(k).file], options_);
  return frame_from_cloud(mcap_cloud(k), source(k), options_);
}

}  // namespace fmcw::io
