// The interrupt's contract (src/io/interrupt.h) where a thread sees the failure the interrupt
// causes: it must end as the interrupt does (128 + the signal), not with an error of its own.
#include "io/interrupt.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/test_util.h"

extern char** environ;

namespace hoof::io {
namespace {

namespace fs = std::filesystem;
using hoof::testing::FreshDir;

TEST(InterruptTest, AFailureTheInterruptCausedEndsWithTheInterruptsCode) {
  // A process waits for a child (as the report waits for gnuplot) when Ctrl-C comes. The
  // interrupt's thread ends the child, so the waiting thread sees it fail, and would report
  // that failure and exit 1 while the interrupt is still removing a large temporary folder (a
  // race KillTest hit once in 16 signals). Yielding to the interrupt, the process must end with
  // 130 and the folder must be gone.
  const fs::path dir = FreshDir("interrupt_yield");
  const fs::path temporary = dir / "temporary";
  fs::create_directories(temporary);
  for (int i = 0; i < 3000; ++i) std::ofstream(temporary / std::to_string(i)) << i;
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    HandleInterrupts();
    TrackTemporary(temporary);
    std::string arg0 = "sleep", arg1 = "30";
    char* argv[] = {arg0.data(), arg1.data(), nullptr};
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    ResetChildSignals(attributes);
    pid_t child = 0;
    if (posix_spawnp(&child, "sleep", nullptr, &attributes, argv, environ) != 0) ::_exit(2);
    TrackChild(child);
    ::kill(::getpid(), SIGINT);
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    YieldToInterrupt();
    ::_exit(1);  // the child's failure, reported as this job's own
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
  EXPECT_FALSE(fs::exists(temporary));
}

}  // namespace
}  // namespace hoof::io
