#include "memory_budget.hpp"

#include <unistd.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::sim {

namespace {
std::string mb(double bytes) {
  std::ostringstream out;
  if (bytes < 1024.0 * 1024.0) {
    out << std::llround(bytes / 1024.0) << " KB";
  } else {
    out << std::llround(bytes / (1024.0 * 1024.0)) << " MB";
  }
  return out.str();
}
}  // namespace

std::uint64_t default_memory_budget_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 4ull << 30;  // unknown: 4 GB
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) / 2;
}

MemoryBudget::MemoryBudget(std::uint64_t limit_bytes)
    : limit_(static_cast<double>(limit_bytes > 0 ? limit_bytes : default_memory_budget_bytes())) {}

void MemoryBudget::add(double bytes, const std::string& where, const std::string& what) {
  total_ += bytes;
  if (!(total_ <= limit_)) {
    throw core::LimitError(where + ": " + what + " would take about " + mb(bytes) + ", and the scenario " +
                           mb(total_) + " in all, over the memory budget of " + mb(limit_) +
                           " (half of this machine's memory unless --max-memory says otherwise)");
  }
}

}  // namespace fmcw::sim
