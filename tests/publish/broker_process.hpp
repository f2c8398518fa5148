// Real brokers for the publish tests: mosquitto (Debian's package) and a Kafka broker in KRaft
// mode (the jars scripts/fetch-kafka.sh copies from Maven Central, run with Debian's OpenJDK),
// each on free loopback ports, started once per test program. Every start and stop is bounded
// in time, and a broker dies with the test: it is killed by the destructor, and by the kernel
// (PR_SET_PDEATHSIG) if the test itself crashes.
#pragma once

#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <arpa/inet.h>
#include <glib.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace jointflow::test {

/// A TCP socket bound to a port of 127.0.0.1 that the kernel chose, then listening when @listening
/// (backlog 16); the port in @port. Throws when there is none.
inline int boundLoopbackSocket(int* port, bool listening) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      (listening && listen(fd, 16) != 0) ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    if (fd >= 0) close(fd);
    throw std::runtime_error("no free loopback port");
  }
  *port = ntohs(addr.sin_port);
  return fd;
}

/// A port nobody listens on now (the kernel's choice for a socket bound to port 0).
inline int freeLoopbackPort() {
  int port = 0;
  close(boundLoopbackSocket(&port, false));
  return port;
}

inline bool portAccepts(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(static_cast<uint16_t>(port));
  const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  close(fd);
  return ok;
}

/// A port on 127.0.0.1 that takes TCP connections (the kernel completes the handshake from its
/// backlog) and never says a word: a broker that hangs before its first answer.
class SilentListener {
 public:
  SilentListener() : fd_(boundLoopbackSocket(&port_, true)) {}
  ~SilentListener() { close(fd_); }
  SilentListener(const SilentListener&) = delete;
  SilentListener& operator=(const SilentListener&) = delete;
  int port() const { return port_; }

 private:
  int port_ = 0;
  int fd_;
};

/// Polls @ready every 50 ms until it holds or @timeout passes.
template <typename F>
bool waitUntil(F ready, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!ready()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return true;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A child process with its output in @log_path.
class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (getppid() != parent) _exit(127);  // the test died before prctl
      const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
      }
      execvp(args[0], args.data());
      _exit(127);
    }
  }
  ~ChildProcess() { kill(SIGKILL, std::chrono::milliseconds(5000)); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool running() {
    if (pid_ <= 0) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      return false;
    }
    return true;
  }
  void signal(int sig) {
    if (pid_ > 0) ::kill(pid_, sig);
  }
  /// The process id while it runs (-1 once it was reaped).
  pid_t pid() const { return pid_; }
  /// Waits at most @timeout for the exit; its status (the exit status, or 128 + the signal that
  /// ended it), or -1 when it still runs.
  int wait(std::chrono::milliseconds timeout) {
    waitUntil([&] { return !running(); }, timeout);
    return running() ? -1 : status_;
  }
  /// Sends @sig and waits for the exit; SIGKILL after @grace. Returns whether it exited.
  bool kill(int sig, std::chrono::milliseconds grace) {
    if (pid_ <= 0) return true;
    ::kill(pid_, sig);
    if (waitUntil([&] { return !running(); }, grace)) return true;
    ::kill(pid_, SIGKILL);
    return waitUntil([&] { return !running(); }, std::chrono::milliseconds(5000));
  }

 private:
  pid_t pid_ = -1;
  int status_ = -1;
};

/// A scratch folder, removed with everything in it.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix) {
    std::string tmpl = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

/// mosquitto on 127.0.0.1:port(). The session store is persisted, so that a subscriber's session
/// survives kill() + start() as it would with a real deployment. mosquitto 2.0.11 saves it when
/// the clock's whole second is more than autosave_interval past the last save: every 2 s here,
/// 1.1-2 s after it starts; waitSaved() waits for a save instead of guessing when it comes.
class Mosquitto {
 public:
  Mosquitto() : dir_("jointflow-mosquitto"), port_(freeLoopbackPort()) {
    setConfig("listener " + std::to_string(port_) + " 127.0.0.1\nallow_anonymous true\n");
  }
  const std::string& dir() const { return dir_.path(); }
  int port() const { return port_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string log() const { return readFile(dir_ / "mosquitto.log"); }
  /// Rewrites the config before start(): @listeners replaces the default listener (a password
  /// file, TLS). Started as root, mosquitto would switch to its own user, who can read neither
  /// this folder nor the test's key files: it stays the test's user.
  void setConfig(const std::string& listeners) {
    std::ofstream conf(dir_ / "mosquitto.conf");
    conf << "user " << g_get_user_name() << "\npersistence true\npersistence_location "
         << dir_.path() << "/\nautosave_interval 1\n"
         << listeners << "log_type error\nlog_type warning\nlog_type notice\nlog_dest stdout\n";
  }

  /// Starts it and waits (at most 10 s) until the port accepts connections.
  bool start(int port_to_wait = 0) {
    process_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{"mosquitto", "-c", dir_ / "mosquitto.conf"},
        dir_ / "mosquitto.log");
    const int port = port_to_wait ? port_to_wait : port_;
    return waitUntil([&] { return portAccepts(port) || !process_->running(); },
                     std::chrono::milliseconds(10000)) &&
           process_->running();
  }
  /// Waits (at most @timeout) until the broker writes its session store after this call, so that
  /// the store holds every subscription made before it. (A fixed 1.5 s sleep here lost the
  /// subscriber's session now and then: a kill before the first save after it subscribed.)
  bool waitSaved(std::chrono::milliseconds timeout) {
    const std::string db = dir_ / "mosquitto.db";
    auto written = [&db] {
      std::error_code error;
      const auto t = std::filesystem::last_write_time(db, error);
      return error ? std::filesystem::file_time_type::min() : t;
    };
    const auto before = written();
    return waitUntil([&] { return written() != before; }, timeout);
  }
  /// SIGKILL: the broker crashes, as in an outage.
  void kill() {
    if (process_) process_->kill(SIGKILL, std::chrono::milliseconds(2000));
    process_.reset();
  }
  ChildProcess* process() { return process_.get(); }

 private:
  TempDir dir_;
  int port_;
  std::unique_ptr<ChildProcess> process_;
};

}  // namespace jointflow::test
