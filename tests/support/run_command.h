#pragma once
// Runs the built hoofimpact program from a test and captures what it prints.
#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <string>

namespace hoof::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// Runs `HOOF_CLI_PATH args` through the shell; stdout and stderr are captured separately.
inline CommandResult RunHoofimpact(const std::string& args) {
  static int counter = 0;
  const std::string err_path = std::string(HOOF_BINARY_DIR) + "/cli-test-stderr-" +
                               std::to_string(::getpid()) + "-" + std::to_string(++counter) +
                               ".txt";  // ctest runs tests in parallel processes
  const std::string cmd = std::string(HOOF_CLI_PATH) + " " + args + " 2>" + err_path;
  CommandResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (FILE* f = std::fopen(err_path.c_str(), "r")) {
    while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) r.err.append(buf.data(), n);
    std::fclose(f);
    std::remove(err_path.c_str());
  }
  return r;
}

}  // namespace hoof::testing
