// Option values out of range are command-line errors (exit 2) that name the option, in every
// command: NaN, infinities and numbers beyond a double on every floating-point option (main()
// puts the check on all of them), and the library validators' bounds before any file is read.
#include <fstream>
#include <iostream>
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
      {"synth footage", "-o /nonexistent-dir/x"},
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
      {"synth footage -o /nonexistent-dir/x --mu 5", "--mu"},
      {"synth footage -o /nonexistent-dir/x --duration-s 0", "--duration-s"},
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

namespace {

/// A struct field with its value ("conditions.surface_angle_rad = 1.65806", "kinematics
/// fit_frames must"): the library's words, which must not reach the user.
bool LeaksAField(const std::string& err) {
  static const std::regex field(
      R"([a-z]+[._][a-z0-9_]+ = -?[0-9.e+-]+ is invalid|kinematics \w+ must|options\.\w+|HtmlReportOptions)");
  return std::regex_search(err, field);
}

TEST(OptionBoundsTest, MessagesUseTheOptionsAndUnitsTheUserTyped) {
  // The user typed degrees: the bound is in degrees, with the value typed, and no radians.
  auto r = RunHoofimpact("simulate --angle-deg 95");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--angle-deg: must be in [0, 80] deg, got 95"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("rad"), std::string::npos) << r.err;
  // Bounds that only the library knows, in the option's name with the value typed.
  const std::string sample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulate --rtol 1", "--rtol: must be in (0, 1e-3], got 1"},
      {"simulate --mass-kg 0", "--mass-kg: must be in [0.0001, 10000] kg, got 0"},
      {"simulate --speed-m-s 0", "--speed-m-s: must be > 0 m/s, got 0"},
      {"analyze " + sample + " -o /nonexistent-dir/x.h5 --fit-frames 2",
       "--fit-frames: must be >= 3, got 2"},
      {"score " + sample + " --max-contact-s 2", "--max-contact-s: must be in [0, 1] s, got 2"},
      {"track " + sample + "/steel_0deg_v3.00_r1 --min-fit-frames 2",
       "--min-fit-frames: must be >= 3, got 2"},
      {"synth -o /nonexistent-dir/x --bit-depth 10", "--bit-depth: must be 8, 12 or 16, got 10"},
      {"synth -o /nonexistent-dir/x --bit-depth 12",
       "--bit-depth: must be 8 or 16 for PNG frames (12 needs the mraw or cine frame format), got "
       "12"},
      {"report /nonexistent-dir/x.h5 --replay-frames 1", "--replay-frames: must be in [2, 400]"},
      {"overlay /nonexistent-dir/x.h5 t1 --slowdown 0", "--slowdown: must be in 1..1000000, got 0"},
      {"overlay /nonexistent-dir/x.h5 t1 --residual-scale 0",
       "--residual-scale: must be in 1..1000 (the residual arrow's magnification), got 0"},
      {"report /nonexistent-dir/x.h5 --residual-scale 5000",
       "--residual-scale: must be in 1..1000 (the residual arrow's magnification), got 5000"},
  };
  for (const auto& [args, message] : cases) {
    r = RunHoofimpact(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_FALSE(LeaksAField(r.err)) << args << "\n" << r.err;
  }
}

TEST(OptionBoundsTest, NoLibraryFieldReachesTheUserOnAnyNumericOption) {
  // Every numeric option of the commands that check before they read or write anything, at
  // two extremes: refused or not, no struct field name and value is shown.
  const std::string fit_csv = std::string(HOOF_BINARY_DIR) + "/option_bounds_fit.csv";
  {
    std::ofstream out(fit_csv);
    out << "v_before_m_s,v_after_m_s\n-3,1.5\n-2,1\n-4,2\n";
  }
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"simulate", ""},
      {"fit", fit_csv},
      {"synth", "-o /nonexistent-dir/x"},
      {"discover", "/nonexistent-dir/x.h5"},
      {"report", "/nonexistent-dir/x.h5"}};
  int refused = 0;
  for (const auto& [command, args] : commands) {
    const auto help = RunHoofimpact(command + " --help");
    const std::regex option(R"((--[a-z0-9-]+) (FLOAT|INT|UINT))");
    for (auto it = std::sregex_iterator(help.out.begin(), help.out.end(), option);
         it != std::sregex_iterator(); ++it) {
      const std::string name = (*it)[1];
      if (name == "--plan-draws") continue;  // needs --plan
      for (const char* value : {"-1e300", "1e300"}) {
        const auto r = RunHoofimpact(command + " " + args + " " + name + " " + value);
        EXPECT_FALSE(LeaksAField(r.err)) << command << " " << name << " " << value << "\n" << r.err;
        if (r.exit_code == 2 && r.err.find(name) != std::string::npos) ++refused;
      }
    }
  }
  std::cout << refused << " values refused, naming the option\n";
  EXPECT_GT(refused, 80);
}

}  // namespace
