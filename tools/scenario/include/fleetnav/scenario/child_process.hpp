#pragma once

#include <csignal>
#include <optional>
#include <string>
#include <vector>

namespace fleetnav::scenario {

/// The whole content of a file ("" when it cannot be read).
std::string ReadWholeFile(const std::string& path);

/// A program run as a child process (posix_spawn) with stdin from /dev/null and stdout and
/// stderr in files. Killed (SIGKILL) and reaped when destroyed while still running. Not
/// thread-safe.
class ChildProcess {
 public:
  /// args[0] is the program's path. started() is false when it could not be spawned.
  ChildProcess(std::vector<std::string> args, const std::string& stdout_path,
               const std::string& stderr_path);
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess();

  bool started() const { return pid_ > 0; }
  bool running();
  int pid() const { return pid_; }

  /// The exit code (128 + signal when killed), or nullopt when it is still running after
  /// timeout_s.
  std::optional<int> Wait(double timeout_s);
  /// Sends `signal` and waits for the exit.
  std::optional<int> Stop(int signal = SIGTERM, double timeout_s = 10.0);

  /// CPU time (user + system) the process used, known once it has exited and been reaped.
  std::optional<double> cpu_s() const { return cpu_s_; }

  std::string Stdout() const { return ReadWholeFile(stdout_path_); }
  std::string Stderr() const { return ReadWholeFile(stderr_path_); }

 private:
  int pid_ = -1;
  std::optional<int> exit_code_;
  std::optional<double> cpu_s_;
  std::string stdout_path_;
  std::string stderr_path_;
};

/// Reads a port number that a server writes to `path` once it serves (0 after timeout_s).
int WaitForPortFile(const std::string& path, double timeout_s = 20.0);

}  // namespace fleetnav::scenario
