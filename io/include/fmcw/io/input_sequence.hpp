#pragma once
// The frames of a command's input in order: one per file (PCD, points, Aeva), or, for --format
// mcap, one per PointCloud2 message of the topic in each MCAP file.

#include <memory>
#include <string>
#include <vector>

#include "fmcw/io/frame_input.hpp"

namespace fmcw::io {

class InputSequence {
 public:
  /// Lists the input's files (list_input_files) and opens each MCAP file. Errors name the file.
  InputSequence(const std::string& input, const InputOptions& options);
  ~InputSequence();
  InputSequence(const InputSequence&) = delete;
  InputSequence& operator=(const InputSequence&) = delete;

  std::size_t size() const { return entries_.size(); }
  /// The frame's file, or "FILE.mcap#K" for the K-th message of an MCAP file.
  std::string source(std::size_t k) const;
  /// A name for per-frame outputs: the file's stem, or "STEM_K" (K with six digits) for MCAP.
  std::string stem(std::size_t k) const;
  bool is_mcap() const { return options_.format == InputFormat::kMcap; }
  /// The k-th frame as the core sees it.
  InputFrame read(std::size_t k);
  /// The k-th frame's cloud: an MCAP message's columns (frame fields only), nothing for others.
  PcdCloud mcap_cloud(std::size_t k);

 private:
  struct Entry {
    std::size_t file = 0;
    std::size_t message = 0;
  };
  InputOptions options_;
  std::vector<std::string> files_;
  std::vector<std::unique_ptr<McapFrames>> mcap_;
  std::vector<Entry> entries_;
};

}  // namespace fmcw::io
