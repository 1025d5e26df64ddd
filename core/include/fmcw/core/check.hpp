#pragma once
// Checks that put the failed condition and the caller's context into the message, and throw the
// typed error of errors.hpp that says whose fault it is.

#include <sstream>
#include <string>

#include "fmcw/core/errors.hpp"

namespace fmcw::core {

/// Builds "what: detail" messages for the errors thrown at public entry points.
template <typename... Parts>
std::string concat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

}  // namespace fmcw::core

/// Throws Error("<context>: <message> (failed: <expr>)") when expr is false.
#define FMCW_CHECK_AS(Error, expr, ...)                                                  \
  do {                                                                                   \
    if (!(expr)) {                                                                       \
      throw Error(::fmcw::core::concat(__VA_ARGS__, " (failed: ", #expr, ")"));          \
    }                                                                                    \
  } while (false)

/// A bad parameter or argument: core::InputError (a std::invalid_argument).
#define FMCW_CHECK_ARG(expr, ...) FMCW_CHECK_AS(::fmcw::core::InputError, expr, __VA_ARGS__)
/// A file that is malformed (the message names it): core::FileError (a std::invalid_argument).
#define FMCW_CHECK_FILE(expr, ...) FMCW_CHECK_AS(::fmcw::core::FileError, expr, __VA_ARGS__)
/// A resource limit (sizes, memory, threads): core::LimitError (a std::runtime_error).
#define FMCW_CHECK_LIMIT(expr, ...) FMCW_CHECK_AS(::fmcw::core::LimitError, expr, __VA_ARGS__)
