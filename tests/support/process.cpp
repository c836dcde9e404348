#include "tests/support/process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace navd::testing {

Process::Process(const std::vector<std::string>& argv, const std::string& log_path) : log_path_(log_path) {
  std::vector<char*> args;
  args.reserve(argv.size());
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    // The child dies with the test process, even if the test crashes.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
    execv(args[0], args.data());
    _exit(127);
  }
}

Process::~Process() {
  if (running()) Stop(SIGTERM, 5.0);
  if (running()) Stop(SIGKILL, 5.0);
}

bool Process::running() {
  if (exited_ || pid_ <= 0) return false;
  const pid_t r = waitpid(pid_, &status_, WNOHANG);
  if (r == pid_) exited_ = true;
  return !exited_;
}

int Process::Wait(double timeout) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  while (running()) {
    if (std::chrono::steady_clock::now() > end) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (WIFEXITED(status_)) return WEXITSTATUS(status_);
  if (WIFSIGNALED(status_)) return 128 + WTERMSIG(status_);
  return -1;
}

int Process::Stop(int signal, double timeout) {
  if (running()) kill(pid_, signal);
  return Wait(timeout);
}

std::string Process::Status() {
  if (running()) return "running";
  if (WIFEXITED(status_)) return "exited with code " + std::to_string(WEXITSTATUS(status_));
  if (WIFSIGNALED(status_)) {
    return "killed by signal " + std::to_string(WTERMSIG(status_)) + " (" + strsignal(WTERMSIG(status_)) + ")";
  }
  return "stopped";
}

std::string Process::Log() const {
  std::ifstream in(log_path_);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string WaitForPortFile(const std::string& path, Process& server, double timeout) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  while (true) {
    std::string port;
    if (std::ifstream in(path); in) in >> port;
    if (!port.empty()) return port;
    if (!server.running()) throw std::runtime_error("the server exited during start-up:\n" + server.Log());
    if (std::chrono::steady_clock::now() > end) throw std::runtime_error("the server did not start:\n" + server.Log());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

CommandResult RunCommand(const std::vector<std::string>& argv, double timeout) {
  const std::string log = MakeTempDir() + "/output.txt";
  Process p(argv, log);
  CommandResult r;
  r.exit_code = p.Wait(timeout);
  if (r.exit_code == -1) p.Stop(SIGKILL, 5.0);
  r.output = p.Log();
  return r;
}

int ReserveDomain() {
  // Domains 100-199 are for tests; users' runs default to 0. The lock fd stays open (and locked)
  // for the life of the process.
  const int start = 100 + static_cast<int>(getpid() % 100);
  for (int i = 0; i < 100; ++i) {
    const int domain = 100 + (start - 100 + i) % 100;
    const std::string path = "/tmp/navd-test-domain-" + std::to_string(domain) + ".lock";
    const int fd = open(path.c_str(), O_RDWR | O_CREAT, 0666);
    if (fd < 0) continue;
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) return domain;
    close(fd);
  }
  throw std::runtime_error("no free DDS test domain in 100..199");
}

namespace {

// The directories MakeTempDir made, removed when the test program exits, after every process it
// started has stopped; NAVD_KEEP_TEST_DIRS=1 keeps them to look at.
class TempDirs {
 public:
  void Add(const std::string& dir) {
    std::lock_guard<std::mutex> lock(mutex_);
    dirs_.push_back(dir);
  }
  ~TempDirs() {
    if (std::getenv("NAVD_KEEP_TEST_DIRS")) return;
    for (const std::string& dir : dirs_) {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  }

 private:
  std::mutex mutex_;
  std::vector<std::string> dirs_;
};

TempDirs& MadeDirs() {
  static TempDirs dirs;
  return dirs;
}

}  // namespace

std::string MakeTempDir() {
  std::string tmpl = "/tmp/navd-test-XXXXXX";
  if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
  MadeDirs().Add(tmpl);
  return tmpl;
}

}  // namespace navd::testing
