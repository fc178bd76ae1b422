// Runs a write in a child process whose files may not grow past a limit (RLIMIT_FSIZE, SIGXFSZ ignored so the
// write fails with EFBIG instead of killing it): a full disk that strikes late, after the file was opened and
// partly written, as the writers' own tests with throwing writers cannot show.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <exception>
#include <functional>

enum class LimitedWrite { threw, returned, crashed };

inline LimitedWrite write_under_file_size_limit(rlim_t bytes, const std::function<void()>& write) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
      write();
    } catch (const std::exception&) {
      _exit(0);
    }
    _exit(1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status)) return LimitedWrite::crashed;
  return WEXITSTATUS(status) == 0 ? LimitedWrite::threw : LimitedWrite::returned;
}
