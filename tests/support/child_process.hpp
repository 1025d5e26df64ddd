#pragma once
// The fmcw CLI started as a separate process that a test can signal and wait for.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace fmcw::test {

struct Child {
  pid_t pid = -1;
  int code = -1;  ///< exit code, or 128 + signal
};

/// Starts `fmcw ARGS...` with stdout and stderr into log_file.
inline Child start_cli(const std::vector<std::string>& args, const std::string& log_file) {
  Child c;
  c.pid = ::fork();
  if (c.pid == 0) {
    const int fd = ::open(log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> argv{const_cast<char*>(FMCW_CLI_PATH)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(FMCW_CLI_PATH, argv.data());
    ::_exit(127);
  }
  return c;
}

inline void wait_for(Child& c) {
  int status = 0;
  ::waitpid(c.pid, &status, 0);
  c.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace fmcw::test
