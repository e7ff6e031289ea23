// Jobs ended from outside at seeded random moments: kill -9 during analyze, run, discover and
// report leaves the previous outputs readable, and the next complete run leaves no temporary
// behind; Ctrl-C (SIGINT) during the same jobs ends them with exit code 130 and leaves no
// temporary at all, at once.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "studyfile/study_file.h"

namespace {

namespace fs = std::filesystem;

/// Where the last job started by this test process wrote its stderr (shown when a job fails).
fs::path StderrLog() {
  return fs::path(HOOF_BINARY_DIR) / "test-output" /
         ("kill-test-" + std::to_string(::getpid()) + ".stderr");
}

/// The stderr of the last job started, to explain a failure.
std::string LastStderr() {
  std::ifstream in(StderrLog());
  std::stringstream text;
  text << in.rdbuf();
  return "\nits stderr:\n" + text.str();
}

/// Starts hoofimpact with `args` (no shell; stdout to /dev/null, stderr to StderrLog()) and
/// returns its pid.
pid_t Start(const std::vector<std::string>& args) {
  std::vector<std::string> all = {HOOF_CLI_PATH};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  fs::create_directories(StderrLog().parent_path());
  const std::string log = StderrLog().string();
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
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

/// An eight-trial study (one surface, two angles, four speeds), rendered once and shared by the
/// tests of this file: enough trials for discovery to run.
fs::path SmallStudy() {
  const fs::path dir = fs::path(HOOF_BINARY_DIR) / "test-output" / "kill-study";
  if (fs::exists(dir / "study.json")) return dir;
  const fs::path tmp = dir.string() + ".tmp-" + std::to_string(::getpid()) + "-0";
  fs::remove_all(tmp);
  fs::create_directories(tmp.parent_path());
  const pid_t pid =
      Start({"synth", "--study", "-o", tmp.string(), "--surfaces", "steel", "--angles-deg", "0,20",
             "--speeds", "2,2.7,3.4,4", "--trials-per-cell", "1", "--seed", "13"});
  const int status = Wait(pid);
  EXPECT_EQ(status, 0) << LastStderr();
  std::error_code ec;
  if (status != 0) {  // nothing half made takes the study's place
    fs::remove_all(tmp, ec);
    return dir;
  }
  // A folder without study.json is what a killed earlier run of this test left: not a study.
  if (!fs::exists(dir / "study.json")) fs::remove_all(dir, ec);
  fs::rename(tmp, dir, ec);  // another test process may have been first
  if (ec) fs::remove_all(tmp, ec);
  return dir;
}

/// Waits (at most 30 s) until process `pid` blocks SIGINT, which main() does first
/// (io::HandleInterrupts), read from /proc/<pid>/status.
bool WaitUntilInterruptsHandled(pid_t pid) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < until) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(status, line))
      if (line.rfind("SigBlk:", 0) == 0 &&
          (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1)) & 1u)
        return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

/// Names holding ".tmp-" in `dir` (not below it).
std::vector<std::string> Temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp-") != std::string::npos)
      out.push_back(e.path().string());
  return out;
}

/// The jobs of these tests, with their outputs under `root`.
struct Jobs {
  fs::path root, analyzed, run, discovered, small_h5, tmpdir;
  std::vector<std::vector<std::string>> args;  // analyze, run, discover, report
  std::vector<double> seconds;                 // of a complete job each

  explicit Jobs(const std::string& name) {
    root = fs::path(HOOF_BINARY_DIR) / "test-output" / name;
    fs::remove_all(root);
    fs::create_directories(root);
    // The report's embedded figures go to the system's temporary folder: this one, to look in.
    tmpdir = root / "tmp";
    fs::create_directories(tmpdir);
    ::setenv("TMPDIR", tmpdir.c_str(), 1);
    const std::string study = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
    analyzed = root / "study.h5";
    run = root / "run";
    small_h5 = root / "small.h5";
    discovered = root / "discovered.h5";
    EXPECT_EQ(Wait(Start({"analyze", SmallStudy().string(), "-o", small_h5.string()})), 0)
        << LastStderr();
    args = {{"analyze", study, "-o", analyzed.string(), "--figures", (root / "figures").string()},
            {"run", study, "-o", run.string()},
            {"discover", small_h5.string(), "-o", discovered.string(), "--jobs", "2"},
            {"report", (run / "study.h5").string(), "-o", (root / "report").string()}};
    // Complete outputs first, and how long each job takes.
    for (const auto& a : args) {
      const auto t0 = std::chrono::steady_clock::now();
      EXPECT_EQ(Wait(Start(a)), 0) << a[0] << LastStderr();
      // Progress is for a terminal: with stderr in a file, discover writes none of its lines.
      if (a[0] == "discover") {
        EXPECT_EQ(LastStderr().find("  discover: "), std::string::npos) << LastStderr();
      }
      seconds.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  }

  /// The previous outputs are whole: the study files read, with their comparison, statistics
  /// and discovery; the report is there; discover's input is as analyze wrote it.
  void ExpectWhole(const std::string& when, std::uintmax_t small_bytes) const {
    EXPECT_NO_THROW(hoof::studyfile::ReadStudyResults(analyzed)) << when;
    EXPECT_NO_THROW(hoof::studyfile::ReadStudyResults(run / "study.h5")) << when;
    EXPECT_NO_THROW(hoof::studyfile::ReadTable(run / "study.h5", "/comparison/surfaces")) << when;
    EXPECT_NO_THROW(hoof::studyfile::ReadTable(run / "study.h5", "/stats/e/cells")) << when;
    EXPECT_NO_THROW(hoof::studyfile::ReadTable(discovered, "/discovery/summary")) << when;
    EXPECT_THROW(hoof::studyfile::ReadTable(small_h5, "/discovery/summary"), std::exception)
        << when;
    EXPECT_EQ(fs::file_size(small_h5), small_bytes) << when;
    EXPECT_GT(fs::file_size(run / "report.html"), 1000u) << when;
    EXPECT_GT(fs::file_size(root / "report" / "report.html"), 1000u) << when;
  }

  std::vector<fs::path> Folders() const {
    return {root, root / "figures", run, run / "figures", root / "report", tmpdir};
  }
};

TEST(KillTest, AKilledJobLeavesThePreviousOutputsReadableAndTheNextRunCleansUp) {
  Jobs jobs("kill");
  ASSERT_FALSE(HasFailure());
  const std::uintmax_t small_bytes = fs::file_size(jobs.small_h5);
  std::mt19937_64 rng(20261123);
  for (int i = 0; i < 24; ++i) {
    const std::size_t job = static_cast<std::size_t>(i) % jobs.args.size();
    std::uniform_real_distribution<double> when(0.0, jobs.seconds[job]);
    const pid_t pid = Start(jobs.args[job]);
    std::this_thread::sleep_for(std::chrono::duration<double>(when(rng)));
    ::kill(pid, SIGKILL);
    Wait(pid);
    jobs.ExpectWhole("kill " + std::to_string(i) + " of " + jobs.args[job][0], small_bytes);
  }
  // The next complete runs leave no temporary behind.
  for (const auto& a : jobs.args) ASSERT_EQ(Wait(Start(a)), 0) << a[0] << LastStderr();
  for (const fs::path& dir : jobs.Folders())
    for (const auto& t : Temporaries(dir)) ADD_FAILURE() << "left behind: " << t;
}

TEST(KillTest, CtrlCEndsAJobWithCode130AndLeavesNoTemporary) {
  Jobs jobs("interrupt");
  ASSERT_FALSE(HasFailure());
  const std::uintmax_t small_bytes = fs::file_size(jobs.small_h5);
  std::mt19937_64 rng(20261124);
  int interrupted = 0;
  for (int i = 0; i < 16; ++i) {
    const std::size_t job = static_cast<std::size_t>(i) % jobs.args.size();
    // Within the first half of a complete job's time: the job still runs when the signal
    // comes even if this run is twice as fast as the measured one (the machine's load varies).
    std::uniform_real_distribution<double> when(0.0, 0.5 * jobs.seconds[job]);
    const double delay = when(rng);
    const pid_t pid = Start(jobs.args[job]);
    // A signal while the program is still being loaded, before main() takes the signals, ends
    // it by the default action before it has written anything; the random moment counts from
    // when main() has taken them.
    EXPECT_TRUE(WaitUntilInterruptsHandled(pid)) << jobs.args[job][0];
    std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    ::kill(pid, SIGINT);
    const int status = Wait(pid);
    const std::string what = "interrupt " + std::to_string(i) + " of " + jobs.args[job][0] +
                             " after " + std::to_string(delay) + " s";
    ASSERT_TRUE(WIFEXITED(status))
        << what << ": ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    // 130 = 128 + SIGINT; 0 when the job finished before the signal came.
    EXPECT_TRUE(WEXITSTATUS(status) == 130 || WEXITSTATUS(status) == 0)
        << what << ": exit " << WEXITSTATUS(status) << LastStderr();
    interrupted += WEXITSTATUS(status) == 130;
    jobs.ExpectWhole(what, small_bytes);
    // No temporary at all, without waiting for a later run to clean up.
    for (const fs::path& dir : jobs.Folders())
      for (const auto& t : Temporaries(dir)) ADD_FAILURE() << what << ": left behind: " << t;
    for (const auto& e : fs::directory_iterator(jobs.tmpdir))
      ADD_FAILURE() << what << ": left behind: " << e.path();
  }
  // Not vacuous: most signals came while a job ran (0 means it had finished first).
  EXPECT_GE(interrupted, 12) << "most signals should come while a job runs";
}

}  // namespace
