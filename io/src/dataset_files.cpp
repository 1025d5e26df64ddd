#include "fmcw/io/dataset_files.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace fmcw::io {

namespace fs = std::filesystem;

std::vector<std::string> list_frame_files(const std::string& input, const std::string& extension) {
  std::error_code ec;
  if (!fs::exists(input, ec)) throw std::invalid_argument("input '" + input + "' does not exist");
  if (fs::is_regular_file(input, ec)) return {input};
  if (!fs::is_directory(input, ec)) throw std::invalid_argument("input '" + input + "' is neither a file nor a folder");
  fs::path dir = fs::path(input) / "frames";
  if (!fs::is_directory(dir, ec)) dir = input;
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file() && entry.path().extension() == extension && entry.path().filename().string()[0] != '.') {
      files.push_back(entry.path().string());
    }
  }
  if (ec) throw std::invalid_argument("cannot list '" + dir.string() + "': " + ec.message());
  if (files.empty()) throw std::invalid_argument("no " + extension + " frames in '" + dir.string() + "'");
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace fmcw::io
