#include "fmcw/io/dataset_files.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::io {

namespace fs = std::filesystem;

std::vector<std::string> list_frame_files(const std::string& input, const std::string& extension) {
  std::error_code ec;
  if (!fs::exists(input, ec)) throw core::FileError("input '" + input + "' does not exist");
  if (fs::is_regular_file(input, ec)) return {input};
  if (!fs::is_directory(input, ec)) throw core::FileError("input '" + input + "' is neither a file nor a folder");
  fs::path dir = fs::path(input) / "frames";
  if (!fs::is_directory(dir, ec)) dir = input;
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file() && entry.path().extension() == extension && entry.path().filename().string()[0] != '.') {
      files.push_back(entry.path().string());
    }
  }
  if (ec) throw core::FileError("cannot list '" + dir.string() + "': " + ec.message());
  if (files.empty()) throw core::FileError("no " + extension + " frames in '" + dir.string() + "'");
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace fmcw::io
