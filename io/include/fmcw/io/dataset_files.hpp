#pragma once
// Finding the frames of an input: one PCD file, or a dataset folder.

#include <string>
#include <vector>

namespace fmcw::io {

/// A file gives itself; a folder gives its frames/*<extension> (a dataset written by
/// `fmcw simulate`) or, without frames/, its own *<extension>, sorted by name. Throws
/// std::invalid_argument naming the path when it does not exist or holds no such file.
std::vector<std::string> list_frame_files(const std::string& input, const std::string& extension = ".pcd");

}  // namespace fmcw::io
