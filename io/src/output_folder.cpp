#include "fmcw/io/output_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/io/atomic_file.hpp"

namespace fmcw::io {

namespace fs = std::filesystem;

namespace {

fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) p = fs::absolute(path).lexically_normal();
  return p;
}

// True when inner is outer or lies below it (both resolved).
bool within(const fs::path& inner, const fs::path& outer) {
  auto o = outer.begin(), i = inner.begin();
  for (; o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

}  // namespace

void refuse_output_over_inputs(const std::string& output, const std::vector<std::string>& inputs) {
  const fs::path out = resolved(output);
  for (const std::string& input : inputs) {
    const fs::path in = resolved(input);
    std::error_code ec;
    const bool is_file = fs::exists(in, ec) && !fs::is_directory(in, ec);
    if (is_file) {
      // Beside the file a same-named output could replace it; a folder below it is another place.
      if (out == in.parent_path()) {
        throw core::InputError("output '" + output + "' is the input file's folder '" + in.parent_path().string() +
                               "': writing there could replace the input; choose an output folder outside it");
      }
    } else if (within(out, in)) {
      throw core::InputError("output '" + output + "' " + (out == in ? "is" : "lies inside") + " the input '" +
                             input + "': writing there could replace the input; choose an output folder outside it");
    }
  }
}

FolderLock::FolderLock(const std::string& dir) : path_((fs::path(dir) / kLockFileName).string()) {
  ensure_writable_directory(dir);
  // A holder removes the file before it lets go: a lock taken on a file that is no longer the
  // one at the path is taken again on the new one.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot lock '" + dir + "': " + path_ + ": " + std::strerror(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      char pid[32] = {};
      const ssize_t n = ::pread(fd, pid, sizeof(pid) - 1, 0);
      ::close(fd);
      if (err != EWOULDBLOCK) throw std::runtime_error("cannot lock '" + dir + "': " + std::strerror(err));
      std::string holder = n > 0 ? std::string(pid, static_cast<std::size_t>(n)) : std::string();
      while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
      throw std::runtime_error("'" + dir + "' is being written by another fmcw process" +
                               (holder.empty() ? std::string() : " (pid " + holder + ")") +
                               "; one writer at a time (its lock: " + path_ + ")");
    }
    struct stat held {}, at_path {};
    if (::fstat(fd, &held) == 0 && ::stat(path_.c_str(), &at_path) == 0 && held.st_ino == at_path.st_ino &&
        held.st_dev == at_path.st_dev) {
      const std::string pid = std::to_string(::getpid()) + "\n";
      if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
        const int err = errno;
        ::close(fd);
        throw std::runtime_error("cannot lock '" + dir + "': " + path_ + ": " + std::strerror(err));
      }
      fd_ = fd;
      return;
    }
    ::close(fd);
  }
  throw std::runtime_error("cannot lock '" + dir + "': its lock file keeps changing");
}

FolderLock::~FolderLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());
  ::close(fd_);
}

bool holds_dataset(const std::string& dir) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(dir) / "dataset.yaml", ec) || fs::is_directory(fs::path(dir) / "frames", ec);
}

bool is_empty_folder(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return true;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.path().filename() != kLockFileName) return false;
  }
  return true;
}

}  // namespace fmcw::io
