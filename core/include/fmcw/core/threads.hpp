#pragma once
// The most threads a parameter struct accepts. More than this on a machine of a few hundred
// cores gains nothing, and OpenMP runtimes fail on thread counts in the thousands (libgomp
// prints "Thread creation failed" or crashes), so a larger count is refused, not passed on.

namespace fmcw::core {

constexpr int kMaxThreads = 256;

}  // namespace fmcw::core
