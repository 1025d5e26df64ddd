#pragma once
// Files appear whole or not at all: write to a temporary name beside the target, then rename.

#include <functional>
#include <ostream>
#include <string>

namespace fmcw::io {

/// Calls write(stream) on a temporary file in the target's folder, flushes and checks it, and
/// renames it over path. On any failure (not writable, disk full, write threw) the temporary
/// file is removed, path is left untouched, and std::runtime_error names the path and the cause.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// Creates a folder and its parents; std::runtime_error naming it when that fails or it is not
/// writable.
void ensure_writable_directory(const std::string& dir);

}  // namespace fmcw::io
