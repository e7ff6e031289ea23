// docs/cli.md's table of every command's options ("Options of every command") against the
// program: every option and positional argument that `hoofimpact <command> --help` lists is a
// row of that command's table, with its short form and its default; every row of the table is
// an option or argument the program has. Hidden, deprecated spellings are listed apart
// ("Deprecated spellings") and must still be accepted.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_command.h"

namespace {

using hoof::testing::RunHoofimpact;

const std::vector<std::string> kCommands = {
    "simulate", "fit",   "stats",   "synth",  "synth footage", "track",   "run",
    "analyze",  "score", "figures", "report", "overlay",       "discover"};

struct Flag {
  std::string name;           ///< "--output", or a positional's name
  std::string short_name;     ///< "-o" or ""
  std::string default_value;  ///< as --help shows it, or ""
};

std::string Trim(const std::string& s) {
  const auto a = s.find_first_not_of(' ');
  const auto b = s.find_last_not_of(' ');
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

/// The options and positionals of `command --help` (CLI11's layout: the names and type in a
/// 30-character column, the description after it or on the next line).
std::map<std::string, Flag> HelpFlags(const std::string& command) {
  const auto help = RunHoofimpact(command + " --help");
  EXPECT_EQ(help.exit_code, 0) << command;
  std::map<std::string, Flag> flags;
  std::istringstream in(help.out);
  bool positionals = false;
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (!line.empty() && line[0] != ' ') positionals = line.rfind("Positionals:", 0) == 0;
    if (line.size() < 3 || line[0] != ' ' || line[1] != ' ' || line[2] == ' ') continue;
    // A name column of 30 characters or more puts the description on the next line, indented.
    const bool alone = i + 1 < lines.size() && lines[i + 1].rfind(std::string(30, ' '), 0) == 0;
    const std::string spec = Trim(alone ? line : line.substr(0, 30));
    Flag f;
    const std::string names = spec.substr(0, spec.find(' '));
    if (positionals) {
      f.name = names;
    } else {
      if (names[0] != '-') continue;
      std::stringstream parts(names);
      for (std::string n; std::getline(parts, n, ',');)
        (n.rfind("--", 0) == 0 ? f.name : f.short_name) = n;
      if (f.name == "--help") continue;
    }
    std::smatch m;
    static const std::regex default_value(R"(=(\S+))");
    const std::string rest = spec.substr(names.size());
    if (std::regex_search(rest, m, default_value)) f.default_value = m[1];
    flags[f.name] = f;
  }
  return flags;
}

/// The rows of `command`'s table in docs/cli.md: first cell the name (in backticks), then the
/// short form, argument, default and meaning.
std::map<std::string, std::vector<std::string>> DocRows(const std::string& command) {
  std::ifstream in(std::string(HOOF_SOURCE_DIR) + "/docs/cli.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto section = doc.find("\n## Options of every command");
  EXPECT_NE(section, std::string::npos);
  const auto start = doc.find("\n### " + command + "\n", section);
  EXPECT_NE(start, std::string::npos) << command;
  std::map<std::string, std::vector<std::string>> rows;
  if (start == std::string::npos) return rows;
  const auto end = doc.find("\n#", start + 5);
  std::istringstream table(doc.substr(start, end - start));
  for (std::string line; std::getline(table, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::string cell;
    // Cells split on '|' outside backticks (a meaning may hold `a|b`).
    bool code = false;
    for (std::size_t i = 1; i < line.size(); ++i) {
      if (line[i] == '`') code = !code;
      if (line[i] == '|' && !code) {
        cells.push_back(Trim(cell));
        cell.clear();
      } else {
        cell += line[i];
      }
    }
    EXPECT_EQ(cells.size(), 5u) << line;
    if (cells.size() != 5) continue;
    std::string name = cells[0];
    name.erase(std::remove(name.begin(), name.end(), '`'), name.end());
    rows[name] = cells;
  }
  return rows;
}

/// Whether the default in the table says `help_default`: the same text, or the same number.
bool SameDefault(const std::string& doc, const std::string& help_default) {
  std::string text = doc;
  text.erase(std::remove(text.begin(), text.end(), '`'), text.end());
  if (text.find(help_default) != std::string::npos) return true;
  char* end = nullptr;
  const double a = std::strtod(help_default.c_str(), &end);
  if (end == help_default.c_str()) return false;
  const double b = std::strtod(text.c_str(), &end);
  return end != text.c_str() && a == b;
}

TEST(CliDocsTest, TheTableListsEveryOptionOfEveryCommand) {
  int checked = 0;
  for (const auto& command : kCommands) {
    const auto help = HelpFlags(command);
    const auto doc = DocRows(command);
    EXPECT_GE(help.size(), 2u) << command;
    for (const auto& [name, flag] : help) {
      const auto row = doc.find(name);
      if (row == doc.end()) {
        ADD_FAILURE() << command << " " << name << " is missing from docs/cli.md's table";
        continue;
      }
      const auto& cells = row->second;
      std::string short_cell = cells[1];
      short_cell.erase(std::remove(short_cell.begin(), short_cell.end(), '`'), short_cell.end());
      EXPECT_EQ(short_cell, flag.short_name) << command << " " << name;
      if (!flag.default_value.empty()) {
        EXPECT_TRUE(SameDefault(cells[3], flag.default_value))
            << command << " " << name << ": the table says '" << cells[3] << "', --help '"
            << flag.default_value << "'";
      }
      EXPECT_FALSE(cells[4].empty()) << command << " " << name;
      ++checked;
    }
    for (const auto& [name, cells] : doc)
      EXPECT_TRUE(help.count(name))
          << command << " " << name << " is in docs/cli.md's table but not in --help";
  }
  EXPECT_GT(checked, 150);
}

TEST(CliDocsTest, DeprecatedSpellingsStillWork) {
  // Each parses (the error, if any, is about the input, not an unknown option).
  const std::string sample = std::string(HOOF_SOURCE_DIR) + "/sample_frames";
  // Each with a later value out of range: the error names that option, so the old spelling
  // before it was taken.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"synth -o /nonexistent-dir/x --threads 2 --fps -5", "--fps"},
      {"analyze " + sample +
           " -o /nonexistent-dir/x.h5 --csv /nonexistent-dir/r.csv --fit-frames 1",
       "--fit-frames"},
      {"stats --csv " + sample + "/steel_0deg_v3.00_r1/trial.json --alpha 2", "--alpha"},
      {"stats " + sample +
           "/steel_0deg_v3.00_r1/trial.json --out-csv /nonexistent-dir/t.csv "
           "--ss-type II",
       "--ss-type"}};
  for (const auto& [args, option] : cases) {
    const auto r = RunHoofimpact(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("not expected"), std::string::npos) << args << "\n" << r.err;
  }
}

}  // namespace
