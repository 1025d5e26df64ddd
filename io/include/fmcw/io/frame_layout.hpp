#pragma once
// One run, one rig: every frame a command reads must have the first frame's shape and heads.
// A frame of another rig (a file copied into the wrong folder) would otherwise be processed or
// evaluated as if it belonged; its stamp may well match.

#include <string>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::io {

class FrameLayoutCheck {
 public:
  /// The first call records the scan's rows, columns and heads (name, column span, seam, mount
  /// pose) with its file. Every later call compares; on a difference it throws
  /// std::invalid_argument naming the file and both layouts, e.g. "b.pcd: 40 x 120 pixels
  /// (rows x cols) with head 'front' [0, 120) differs from a.pcd, the first frame: 150 x 600
  /// pixels (rows x cols) with heads 'left' [0, 200), ...; every frame must come from one rig".
  void check(const core::Scan& scan, const std::string& file);

  bool has_first() const { return !first_file_.empty(); }

 private:
  int rows_ = 0;
  int cols_ = 0;
  std::vector<core::HeadInfo> heads_;
  std::string first_file_;
};

}  // namespace fmcw::io
