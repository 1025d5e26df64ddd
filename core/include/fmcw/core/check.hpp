#pragma once
// Argument checks that put the failed condition and the caller's context into the message.

#include <sstream>
#include <stdexcept>
#include <string>

namespace fmcw::core {

/// Builds "what: detail" messages for std::invalid_argument at public entry points.
template <typename... Parts>
std::string concat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

}  // namespace fmcw::core

/// Throws std::invalid_argument("<context>: <message> (failed: <expr>)") when expr is false.
#define FMCW_CHECK_ARG(expr, ...)                                                          \
  do {                                                                                     \
    if (!(expr)) {                                                                         \
      throw std::invalid_argument(::fmcw::core::concat(__VA_ARGS__, " (failed: ", #expr, ")")); \
    }                                                                                      \
  } while (false)
