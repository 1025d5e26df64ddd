#include "fmcw/io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace fmcw::io {

namespace fs = std::filesystem;

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const fs::path target(path);
  const fs::path tmp = target.parent_path() / (".tmp." + target.filename().string() + "." + std::to_string(::getpid()));
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    }
    // errno of the failed write(2) says why: ENOSPC on a full disk, EDQUOT over a quota, EIO.
    errno = 0;
    write(out);
    out.flush();
    if (!out) throw std::runtime_error("cannot write '" + path + "': " + (errno ? std::strerror(errno) : "write failed"));
    out.close();
    if (out.fail()) throw std::runtime_error("cannot write '" + path + "': " + (errno ? std::strerror(errno) : "close failed"));
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw std::runtime_error("cannot write '" + path + "': rename failed: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

void ensure_writable_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create output folder '" + dir + "': " + ec.message());
  if (!fs::is_directory(dir, ec)) throw std::runtime_error("output path '" + dir + "' is not a folder");
  if (::access(dir.c_str(), W_OK) != 0) {
    throw std::runtime_error("output folder '" + dir + "' is not writable: " + std::strerror(errno));
  }
}

}  // namespace fmcw::io
