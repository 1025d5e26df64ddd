#pragma once
// Finding the frames of an input: one PCD file, or a dataset folder.

#include <string>
#include <vector>

namespace fmcw::io {

/// A .pcd file gives itself; a folder gives its frames/*.pcd (a dataset written by
/// `fmcw simulate`) or, without frames/, its own *.pcd, sorted by name. Throws
/// std::invalid_argument naming the path when it does not exist or holds no PCD.
std::vector<std::string> list_frame_files(const std::string& input);

}  // namespace fmcw::io
