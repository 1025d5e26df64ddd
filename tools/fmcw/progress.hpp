#pragma once
// Progress on stderr: a redrawn bar on a terminal, a plain line every ~10 % otherwise.

#include <string>

namespace fmcw::cli {

class Progress {
 public:
  explicit Progress(std::string label);
  void update(int done, int total);

 private:
  std::string label_;
  bool tty_;
  int last_decile_ = -1;
};

}  // namespace fmcw::cli
