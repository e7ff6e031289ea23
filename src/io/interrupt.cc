#include "io/interrupt.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>
#include <shared_mutex>
#include <string>
#include <system_error>
#include <thread>

namespace hoof::io {
namespace {

struct Registry {
  std::shared_mutex creating;  // shared while a temporary is made; the interrupt takes it whole
  std::mutex mutex;
  std::set<std::filesystem::path> temporaries;
  std::set<pid_t> children;
};

/// Set first when an interrupt begins: a failure it causes in another thread (a child it ended,
/// a temporary it removed) then yields to it (YieldToInterrupt).
std::atomic<bool> interrupting{false};

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
  interrupting.store(true);
  Registry& r = TheRegistry();
  std::size_t removed = 0;
  // Held until the process ends: the temporaries under way are made first, and no more after.
  r.creating.lock();
  {
    std::lock_guard<std::mutex> lock(r.mutex);
    // A child (gnuplot) writes temporaries of its own: it is ended, and waited for, first.
    for (const pid_t child : r.children) {
      ::kill(child, SIGKILL);
      while (::waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
      }  // ECHILD: the thread that started it has waited for it already
    }
    for (const auto& path : r.temporaries) {
      // A folder can gain a file from a thread that is writing into it while it is removed;
      // that file is removed on the next pass (no new one can start once the folder is gone).
      std::error_code ec;
      for (int pass = 0; pass < 10; ++pass) {
        const auto count = std::filesystem::remove_all(path, ec);
        if (!ec) {
          removed += count > 0;
          break;
        }
      }
    }
  }
  const std::string message =
      std::string("\nhoofimpact: interrupted (") + ::strsignal(signal) + "); " +
      std::to_string(removed) +
      " unfinished output(s) removed; outputs already written are complete\n";
  (void)!::write(STDERR_FILENO, message.data(), message.size());
  ::_exit(128 + signal);
}

}  // namespace

// Re-entrant within a thread (a temporary made while making another): the shared lock is taken
// once per thread, as taking it twice would be undefined.
thread_local int creating_depth = 0;

CreatingTemporary::CreatingTemporary() {
  if (creating_depth++ == 0) TheRegistry().creating.lock_shared();
}

CreatingTemporary::~CreatingTemporary() {
  if (--creating_depth == 0) TheRegistry().creating.unlock_shared();
}

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
  posix_spawnattr_setflags(
      &attributes, static_cast<short>(flags | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF));
}

void YieldToInterrupt() {
  if (!interrupting.load()) return;
  for (;;) std::this_thread::sleep_for(std::chrono::hours(1));  // until OnInterrupt's _exit
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
