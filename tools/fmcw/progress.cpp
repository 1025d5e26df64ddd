#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace fmcw::cli {

Progress::Progress(std::string label) : label_(std::move(label)), tty_(::isatty(STDERR_FILENO) != 0) {}

void Progress::update(int done, int total) {
  if (total <= 0) return;
  if (tty_) {
    constexpr int kWidth = 40;
    const int filled = done * kWidth / total;
    std::fprintf(stderr, "\r%s [%.*s%*s] %d/%d", label_.c_str(), filled, "########################################",
                 kWidth - filled, "", done, total);
    if (done == total) std::fputc('\n', stderr);
    std::fflush(stderr);
    return;
  }
  const int decile = done * 10 / total;
  if (decile != last_decile_ || done == total) {
    last_decile_ = decile;
    std::fprintf(stderr, "%s: %d/%d frames\n", label_.c_str(), done, total);
  }
}

}  // namespace fmcw::cli
