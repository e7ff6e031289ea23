// Option values out of range are command-line errors (exit 2) that name the option, in every
// command: NaN, infinities and numbers beyond a double on every floating-point option (main()
// puts the check on all of them), and the library validators' bounds before any file is read.
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_command.h"

namespace {

using hoof::testing::RunHoofimpact;

/// The floating-point options that `hoofimpact <command> --help` lists.
std::vector<std::string> FloatOptions(const std::string& command) {
  const auto help = RunHoofimpact(command + " --help");
  std::vector<std::string> out;
  const std::regex option(R"((--[a-z0-9-]+) FLOAT)");
  for (auto it = std::sregex_iterator(help.out.begin(), help.out.end(), option);
       it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

TEST(OptionBoundsTest, NoFloatingPointOptionTakesNanOrInfinity) {
  const std::string sample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
  // Each command with the arguments it needs to get as far as its options.
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"simulate", ""},
      {"fit", ""},
      {"synth", "-o /nonexistent-dir/x"},
      {"analyze", sample + " -o /nonexistent-dir/x.h5"},
      {"run", sample + " -o /nonexistent-dir/x"},
      {"track", sample + "/steel_0deg_v3.00_r1"},
      {"discover", "/nonexistent-dir/x.h5"},
      {"score", sample}};
  int checked = 0;
  for (const auto& [command, args] : commands) {
    const auto options = FloatOptions(command);
    EXPECT_FALSE(options.empty()) << command;
    // Three per command, spread over its list, each with a different bad value.
    const char* values[] = {"nan", "inf", "1e999"};
    for (std::size_t k = 0; k < 3 && k < options.size(); ++k) {
      const std::string& option = options[k * options.size() / 3];
      const auto r = RunHoofimpact(command + " " + args + " " + option + " " + values[k]);
      EXPECT_EQ(r.exit_code, 2) << command << " " << option << " " << values[k] << "\n" << r.err;
      EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
      ++checked;
    }
  }
  EXPECT_GE(checked, 20);
}

TEST(OptionBoundsTest, LibraryBoundsAreCommandLineErrorsNamingTheOption) {
  const std::string sample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"analyze " + sample + " -o /nonexistent-dir/x.h5 --fit-frames 1", "--fit-frames"},
      {"analyze " + sample + " -o /nonexistent-dir/x.h5 --exposure-s 5", "--exposure-s"},
      {"run " + sample + " -o /nonexistent-dir/x --max-contact-s 2", "--max-contact-s"},
      {"run " + sample + " -o /nonexistent-dir/x --alpha 0.7", "--alpha"},
      {"score " + sample + " --fit-frames 2", "--fit-frames"},
      {"synth -o /nonexistent-dir/x --fps -5", "--fps"},
      {"synth -o /nonexistent-dir/x --black-level 0.9", "--black-level"},
      {"synth -o /nonexistent-dir/x --mu 1e300", "--mu"},
      {"synth -o /nonexistent-dir/x --tilt-rate-deg-s 1e6", "--tilt-rate-deg-s"},
      {"report /nonexistent-dir/x.h5 --replay-frames 1", "--replay-frames"},
      {"simulate --fps 0", "--fps"},
  };
  for (const auto& [args, option] : cases) {
    const auto r = RunHoofimpact(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << "\n" << r.err;
  }
}

}  // namespace
