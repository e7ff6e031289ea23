#include "io/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <system_error>
#include <thread>

namespace hoof::io {
namespace {

struct Registry {
  std::mutex mutex;
  std::set<std::filesystem::path> temporaries;
  std::set<pid_t> children;
};

Registry& TheRegistry() {
  static Registry* registry = new Registry;  // never destroyed: the signal thread may outlive main
  return *registry;
}

sigset_t InterruptSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

[[noreturn]] void OnInterrupt(int signal) {
  Registry& r = TheRegistry();
  std::size_t removed = 0;
  {
    std::lock_guard<std::mutex> lock(r.mutex);
    for (const pid_t child : r.children) ::kill(child, SIGTERM);
    for (const auto& path : r.temporaries) {
      std::error_code ec;
      if (std::filesystem::remove_all(path, ec) > 0) ++removed;
    }
  }
  const std::string message = std::string("\nhoofimpact: interrupted (") + ::strsignal(signal) + "); " +
                              std::to_string(removed) +
                              " unfinished output(s) removed; outputs already written are complete\n";
  (void)!::write(STDERR_FILENO, message.data(), message.size());
  ::_exit(128 + signal);
}

}  // namespace

void TrackTemporary(const std::filesystem::path& path) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.temporaries.insert(path);
}

void UntrackTemporary(const std::filesystem::path& path) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.temporaries.erase(path);
}

void TrackChild(pid_t pid) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.children.insert(pid);
}

void UntrackChild(pid_t pid) {
  Registry& r = TheRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.children.erase(pid);
}

void ResetChildSignals(posix_spawnattr_t& attributes) {
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  const sigset_t defaults = InterruptSignals();
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  short flags = 0;
  posix_spawnattr_getflags(&attributes, &flags);
  posix_spawnattr_setflags(&attributes, static_cast<short>(flags | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF));
}

void HandleInterrupts() {
  const sigset_t set = InterruptSignals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);  // inherited by every thread started after this
  (void)TheRegistry();
  std::thread([set] {
    int signal = 0;
    while (sigwait(&set, &signal) != 0) {
    }
    OnInterrupt(signal);
  }).detach();
}

}  // namespace hoof::io
