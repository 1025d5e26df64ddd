#include "fmcw/io/frame_layout.hpp"

#include <stdexcept>

#include "fmcw/core/check.hpp"

namespace fmcw::io {

using core::concat;

namespace {
constexpr const char* kOneRig = "; every frame must come from one rig";
// Mount poses are written with 17 digits and read back exactly; this only absorbs rounding.
constexpr double kPoseTolerance = 1e-9;

std::string describe(int rows, int cols, const std::vector<core::HeadInfo>& heads) {
  std::string text = concat(rows, " x ", cols, " pixels (rows x cols) with head", heads.size() == 1 ? "" : "s");
  for (std::size_t h = 0; h < heads.size(); ++h) {
    text += concat(h == 0 ? " '" : ", '", heads[h].name, "' [", heads[h].col_begin, ", ", heads[h].col_end, ")");
  }
  return text;
}

std::string describe_pose(const core::HeadInfo& head) {
  const Eigen::Vector3d t = head.T_rig_head.translation();
  const Eigen::Quaterniond q(head.T_rig_head.linear());
  return concat("(", t.x(), ", ", t.y(), ", ", t.z(), "), rotation quaternion (", q.w(), ", ", q.x(), ", ", q.y(), ", ",
                q.z(), ")");
}

bool same_spans(const std::vector<core::HeadInfo>& a, const std::vector<core::HeadInfo>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t h = 0; h < a.size(); ++h) {
    if (a[h].name != b[h].name || a[h].col_begin != b[h].col_begin || a[h].col_end != b[h].col_end) return false;
  }
  return true;
}
}  // namespace

void FrameLayoutCheck::check(const core::Scan& scan, const std::string& file) {
  if (!has_first()) {
    rows_ = scan.rows;
    cols_ = scan.cols;
    heads_ = scan.heads;
    first_file_ = file;
    return;
  }
  if (scan.rows != rows_ || scan.cols != cols_ || !same_spans(scan.heads, heads_)) {
    throw core::FileError(concat(file, ": ", describe(scan.rows, scan.cols, scan.heads), " differs from ",
                                 first_file_, ", the first frame: ", describe(rows_, cols_, heads_), kOneRig));
  }
  for (std::size_t h = 0; h < heads_.size(); ++h) {
    const core::HeadInfo& head = scan.heads[h];
    const core::HeadInfo& first = heads_[h];
    const std::string which = concat(file, ": head '", head.name, "' [", head.col_begin, ", ", head.col_end, ")");
    if (head.stitched_to_next != first.stitched_to_next) {
      throw core::FileError(concat(which, " is ", head.stitched_to_next ? "" : "not ",
                                   "stitched to the next where the first frame's is",
                                   first.stitched_to_next ? "" : " not", " (", first_file_, ")", kOneRig));
    }
    const double pose_difference = (head.T_rig_head.matrix() - first.T_rig_head.matrix()).cwiseAbs().maxCoeff();
    if (!(pose_difference <= kPoseTolerance)) {
      throw core::FileError(concat(which, " is mounted at ", describe_pose(head), " where the first frame's is at ",
                                   describe_pose(first), " (", first_file_, ")", kOneRig));
    }
  }
}

}  // namespace fmcw::io
