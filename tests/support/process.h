#pragma once
// Real child processes for integration tests: started with fork/exec, output captured to a file,
// and terminated (SIGTERM, then SIGKILL) when the handle goes away, so no test leaves one behind.
#include <sys/types.h>

#include <string>
#include <vector>

namespace navd::testing {

class Process {
 public:
  // Starts `argv[0]` with the arguments; stdout and stderr go to `log_path`.
  Process(const std::vector<std::string>& argv, const std::string& log_path);
  ~Process();
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  // Sends `signal` and waits up to `timeout` seconds; returns the exit code (128+signal if killed),
  // or -1 when it did not exit in time.
  int Stop(int signal, double timeout);
  // Waits up to `timeout` seconds for a natural exit; -1 when still running.
  int Wait(double timeout);
  std::string Log() const;
  // "running", "exited with code N" or "killed by signal N (name)": why a test lost its server.
  std::string Status();

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool exited_ = false;
  std::string log_path_;
};

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr, interleaved
};

// Runs a command to completion (bounded by `timeout` seconds) and returns its exit code and output.
CommandResult RunCommand(const std::vector<std::string>& argv, double timeout = 30.0);

// Waits up to `timeout` seconds for the port a server wrote to `path` (navd --port-file) and
// returns it. Throws std::runtime_error, with the server's log, when `server` exits first or the
// time runs out.
std::string WaitForPortFile(const std::string& path, Process& server, double timeout);

// A DDS domain id no other test process on this machine holds, reserved by an flock on a file
// in /tmp until the process exits. Integration tests run in parallel, one domain each.
int ReserveDomain();

// A fresh temporary directory for the test's files, removed when the test program exits
// (NAVD_KEEP_TEST_DIRS=1 keeps it).
std::string MakeTempDir();

}  // namespace navd::testing
