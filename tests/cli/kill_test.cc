// kill -9 at seeded random moments during analyze, run and report (issue 13): the previous
// outputs stay readable every time, and the next complete run leaves no temporary behind.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "studyfile/study_file.h"

namespace {

namespace fs = std::filesystem;

/// Starts hoofimpact with `args` (no shell; output to /dev/null) and returns its pid.
pid_t Start(const std::vector<std::string>& args) {
  std::vector<std::string> all = {HOOF_CLI_PATH};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, HOOF_CLI_PATH, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  EXPECT_EQ(rc, 0);
  return pid;
}

int Wait(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

/// Names holding ".tmp-" in `dir` (not below it).
std::vector<std::string> Temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) out.push_back(e.path().string());
  return out;
}

TEST(KillTest, AKilledJobLeavesThePreviousOutputsReadableAndTheNextRunCleansUp) {
  const fs::path root = fs::path(HOOF_BINARY_DIR) / "test-output" / "kill";
  fs::remove_all(root);
  fs::create_directories(root);
  const std::string study = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
  const fs::path analyzed = root / "study.h5", run = root / "run";
  const std::vector<std::string> analyze_args = {"analyze", study, "-o", analyzed.string(), "--figures",
                                                 (root / "figures").string()};
  const std::vector<std::string> run_args = {"run", study, "-o", run.string()};
  const std::vector<std::string> report_args = {"report", (run / "study.h5").string(), "-o", (root / "report").string()};
  // Complete outputs first, and how long each job takes.
  std::vector<double> seconds;
  for (const auto* args : {&analyze_args, &run_args, &report_args}) {
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(Wait(Start(*args)), 0);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::mt19937_64 rng(20261123);
  for (int i = 0; i < 21; ++i) {
    const int job = i % 3;
    const auto& args = job == 0 ? analyze_args : job == 1 ? run_args : report_args;
    std::uniform_real_distribution<double> when(0.0, seconds[static_cast<std::size_t>(job)]);
    const pid_t pid = Start(args);
    std::this_thread::sleep_for(std::chrono::duration<double>(when(rng)));
    ::kill(pid, SIGKILL);
    Wait(pid);
    // The previous outputs are whole: the study files read, the report is there.
    EXPECT_NO_THROW(hoof::studyfile::ReadStudyResults(analyzed)) << "kill " << i;
    EXPECT_NO_THROW(hoof::studyfile::ReadStudyResults(run / "study.h5")) << "kill " << i;
    // and run's study file is complete: the comparison and the statistics are in it.
    EXPECT_NO_THROW(hoof::studyfile::ReadTable(run / "study.h5", "/comparison/surfaces")) << "kill " << i;
    EXPECT_NO_THROW(hoof::studyfile::ReadTable(run / "study.h5", "/stats/e/cells")) << "kill " << i;
    EXPECT_GT(fs::file_size(run / "report.html"), 1000u) << "kill " << i;
  }
  // The next complete runs leave no temporary behind.
  ASSERT_EQ(Wait(Start(analyze_args)), 0);
  ASSERT_EQ(Wait(Start(run_args)), 0);
  for (const fs::path& dir : {root, root / "figures", run, run / "figures"})
    for (const auto& t : Temporaries(dir)) ADD_FAILURE() << "left behind: " << t;
}

}  // namespace
