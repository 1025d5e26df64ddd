#pragma once
// Typed errors, so that a caller tells a bad parameter from a bad file from a resource limit (the
// CLI picks its exit code by them, the Python module its exception type). Each derives from the
// standard exception the project threw before, so that a catch of std::invalid_argument or
// std::runtime_error keeps working.

#include <stdexcept>
#include <string>

namespace fmcw::core {

/// Bad input or parameters at a public entry point: a params struct, an option, an array of the
/// wrong shape, an output folder that may not be used. FMCW_CHECK_ARG throws it.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A file that is missing, unreadable or malformed: a PCD, a scenario, a mesh, a dataset.yaml, a
/// truth table, or a dataset folder whose files disagree. The message names the file (and the
/// line, key or point where it can). Derives from std::invalid_argument, as bad files were
/// reported before (and as readers' tests catch them); FMCW_CHECK_FILE throws it.
class FileError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A resource limit: the memory budget, a size beyond what a reader or the simulator takes
/// (pixels, points, header bytes, nesting), a thread count. FMCW_CHECK_LIMIT throws it.
class LimitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// For a catch block that says where an error happened: rethrows the exception being handled
/// with `before` and `after` around its message, as the same kind of error (InputError,
/// FileError, LimitError, or else std::invalid_argument or std::runtime_error). Any other
/// exception (std::bad_alloc, ...) is rethrown as it is. Call it only inside a catch block.
[[noreturn]] inline void rethrow_with_context(const std::string& before, const std::string& after = "") {
  try {
    throw;
  } catch (const LimitError& e) {
    throw LimitError(before + e.what() + after);
  } catch (const FileError& e) {
    throw FileError(before + e.what() + after);
  } catch (const InputError& e) {
    throw InputError(before + e.what() + after);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(before + e.what() + after);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(before + e.what() + after);
  }
}

/// For a catch block around checks of what a file holds (a reader handing its values to a
/// params' or a scan's validation): rethrows the exception being handled with `before` (the
/// file, and where in it) before its message. A LimitError stays one; any std::invalid_argument
/// (an InputError of the check) becomes a FileError: the file holds the bad value. Any other
/// exception is rethrown as it is. Call it only inside a catch block.
[[noreturn]] inline void rethrow_as_file_error(const std::string& before) {
  try {
    throw;
  } catch (const LimitError& e) {
    throw LimitError(before + e.what());
  } catch (const std::invalid_argument& e) {
    throw FileError(before + e.what());
  }
}

}  // namespace fmcw::core
