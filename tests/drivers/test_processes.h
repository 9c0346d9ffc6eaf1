// Helper processes the driver tests start and stop themselves (CI runs no services): an Xvfb
// X server and the arv-fake-gv-camera-0.8 GigE Vision fake. Each helper records the PID of the
// process it started and, on destruction, signals only that PID and reaps it. Nothing listens
// on a network interface other than loopback (Xvfb: -nolisten tcp, a Unix socket only; the fake
// camera: -i 127.0.0.1).
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace zbrdf::testing {

class ChildProcess {
 public:
  ChildProcess() = default;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() { Stop(); }

  // fork + execvp with stdout/stderr sent to /dev/null; `keep_fd` stays open in the child.
  void Start(const std::vector<std::string>& argv, int keep_fd = -1) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      const int null = open("/dev/null", O_WRONLY);
      if (null >= 0) {
        dup2(null, STDOUT_FILENO);
        dup2(null, STDERR_FILENO);
      }
      for (int fd = 3; fd < 1024; ++fd) {
        if (fd != keep_fd) close(fd);
      }
      execvp(args[0], args.data());
      _exit(127);
    }
  }

  pid_t pid() const { return pid_; }
  bool Running() {
    if (pid_ <= 0) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return false;
    }
    return true;
  }

  // Sends `signal` to the recorded PID and reaps it (SIGKILL after 3 s if it lingers).
  void Stop(int signal_number = SIGTERM) {
    if (pid_ <= 0) return;
    kill(pid_, signal_number);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    int status = 0;
    while (waitpid(pid_, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) {
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

// Xvfb on a display number it picks itself (-displayfd), so parallel tests never collide.
class XvfbServer {
 public:
  explicit XvfbServer(const std::string& screen = "1024x768x24") {
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
    process_.Start({"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0", screen,
                    "-nolisten", "tcp", "-noreset"},
                   fds[1]);
    close(fds[1]);
    std::string number;
    pollfd pfd{fds[0], POLLIN, 0};
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (number.empty() || number.back() != '\n') {
      const int left = static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                            deadline - std::chrono::steady_clock::now())
                                            .count());
      if (left <= 0 || poll(&pfd, 1, left) <= 0) break;
      char c = 0;
      if (read(fds[0], &c, 1) != 1) break;
      number += c;
    }
    close(fds[0]);
    if (number.empty() || number.back() != '\n') {
      process_.Stop(SIGKILL);
      throw std::runtime_error("Xvfb did not report a display number within 10 s");
    }
    number.pop_back();
    display_ = ":" + number;
  }
  const std::string& display() const { return display_; }
  pid_t pid() const { return process_.pid(); }
  void Stop() { process_.Stop(); }

 private:
  ChildProcess process_;
  std::string display_;
};

// True once some process has a UDP socket bound to 127.0.0.1:port (/proc/net/udp).
inline bool UdpPortBoundOnLoopback(int port) {
  std::ifstream table("/proc/net/udp");
  std::string line;
  char wanted[32];
  std::snprintf(wanted, sizeof(wanted), "0100007F:%04X", port);
  while (std::getline(table, line)) {
    if (line.find(wanted) != std::string::npos) return true;
  }
  return false;
}

// arv-fake-gv-camera-0.8 -i 127.0.0.1 as a separate process; ready once its GVCP port is bound.
class FakeCameraProcess {
 public:
  explicit FakeCameraProcess(const std::string& serial) {
    if (UdpPortBoundOnLoopback(3956)) {
      throw std::runtime_error("127.0.0.1:3956 is already bound (another fake camera running?)");
    }
    process_.Start({"arv-fake-gv-camera-0.8", "-i", "127.0.0.1", "-s", serial});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!UdpPortBoundOnLoopback(3956)) {
      if (!process_.Running() || std::chrono::steady_clock::now() > deadline) {
        process_.Stop(SIGKILL);
        throw std::runtime_error("arv-fake-gv-camera-0.8 did not bind 127.0.0.1:3956");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  pid_t pid() const { return process_.pid(); }
  void Stop(int signal_number = SIGTERM) { process_.Stop(signal_number); }

 private:
  ChildProcess process_;
};

}  // namespace zbrdf::testing
