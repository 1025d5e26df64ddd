#pragma once
// Frames of an AevaScenes sequence folder (io/aevascenes.hpp) for the evaluation: the six
// lidars' scans with the annotations as ground truth, the ego compensation undone with the
// sequence's own ego poses so that every method's ego velocity is measured and compared.

#include "fmcw/eval/frame_source.hpp"
#include "fmcw/io/aevascenes.hpp"

namespace fmcw::eval {

/// True when dir holds an AevaScenes sequence.json.
bool is_aevascenes_sequence(const std::string& dir);

class AevaScenesSource : public FrameSource {
 public:
  /// Reads DIR/sequence.json and frame 0 (core::FileError naming the file at fault);
  /// max_frames > 0 keeps the first max_frames frames. options.to_sensor_frame is set.
  explicit AevaScenesSource(const std::string& dir, int max_frames = 0, io::AevaScenesOptions options = {});
  std::size_t size() const override { return frames_; }
  core::Frame frame(std::size_t k) override;
  std::string describe(std::size_t k) const override;
  const SourceInfo& info() const override { return info_; }

 private:
  io::AevaScenesSequence sequence_;
  io::AevaScenesOptions options_;
  core::ClassTable classes_ = core::ClassTable::builtin();
  std::size_t frames_ = 0;
  SourceInfo info_;
  io::FrameLayoutCheck layout_;
};

}  // namespace fmcw::eval
