#pragma once
// Guards for an output folder: never one of the inputs, and one writer at a time.

#include <string>
#include <vector>

namespace fmcw::io {

/// Throws std::invalid_argument, before anything is written, when output is an input folder or
/// lies inside one, or is the folder of an input file (where a same-named output file would
/// replace it). Paths are compared after resolving symbolic links, "..", and the working folder;
/// a path that does not exist yet is compared as written.
void refuse_output_over_inputs(const std::string& output, const std::vector<std::string>& inputs);

/// The name of the lock file a FolderLock keeps in its folder while it holds it.
inline constexpr const char* kLockFileName = ".fmcw.lock";

/// An exclusive lock on a folder for as long as the object lives: flock(2) on kLockFileName
/// inside it, which holds the owner's pid. A second FolderLock on the same folder, from this or
/// any process of the machine, fails at once with std::runtime_error naming the folder and the
/// holder's pid. The folder is created if missing. The lock file is removed on release; a lock
/// file left by a killed process is no lock (the kernel dropped its flock) and is taken over.
class FolderLock {
 public:
  explicit FolderLock(const std::string& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  std::string path_;
  int fd_ = -1;
};

/// True when dir holds a dataset, or what a stopped writer of one left: dataset.yaml or frames/.
/// --overwrite replaces such a folder and no other.
bool holds_dataset(const std::string& dir);

/// True when dir does not exist or holds nothing but a lock file.
bool is_empty_folder(const std::string& dir);

}  // namespace fmcw::io
