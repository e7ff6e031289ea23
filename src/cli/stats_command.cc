// hoofimpact stats: one-way ANOVA with its checks (Bartlett, Welch, Box-Cox, Fisher's LSD) and
// an optional two-way table, for a response column of a CSV table grouped by factor columns
// (--csv), or the paper's tables for e and mu_eff of a whole study file (positional STUDY_H5:
// by surface, angle and speed, and surface x angle), stored back into the file under /stats.
// Only arguments and reading live here; the statistics are in hoof::stats, the study's tables
// in study/statistics.h, and their text, JSON and CSV in study/statistics_text.h.
#include <cctype>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "io/csv.h"
#include "stats/grouping.h"
#include "stats/one_way_analysis.h"
#include "stats/two_way_anova.h"
#include "study/statistics.h"
#include "study/statistics_text.h"
#include "studyfile/study_file.h"

namespace hoof::cli {
namespace {

using nlohmann::json;

struct StatsArgs {
  // Input: a study file or a CSV table (positional; --csv, the earlier spelling of a table,
  // still works); --response/--factor are checked in the callback, not by CLI11, because only
  // a table needs them.
  std::string input;
  std::string study_h5;
  std::string shown_as;  ///< the study file's name in messages, when study_h5 is a temporary
  std::string csv_path;
  std::string response;
  std::string factor;
  std::string factor2;
  double alpha = 0.05;
  std::string ss_type = "III";
  bool json = false;
  std::string out_csv;
};

/// The columns the analysis needs, read from the CSV table: the rows with a value of the
/// response.
struct StatsInput {
  std::string source;
  std::vector<double> response;
  std::vector<std::string> factor;
  std::vector<std::string> factor2;
  /// The lines of the rows left out: the response is empty or NaN there (not measured, or not
  /// defined, as mu_eff of a normal impact in results.csv).
  std::vector<std::size_t> left_out_lines;
};

/// Whether `text` says "no value": empty, or NaN in any case.
bool NoValue(const std::string& text) {
  std::string lower = text;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower.empty() || lower == "nan";
}

/// A factor column as labels, for the rows `rows`; an empty field is an error naming file, line
/// and column.
std::vector<std::string> ReadLabels(const io::CsvTable& table, const std::string& column,
                                    const std::vector<std::size_t>& rows) {
  const std::size_t c = table.Column(column);
  std::vector<std::string> labels;
  for (std::size_t r : rows) {
    const std::string& text = table.Text(r, c);
    if (text.empty()) {
      std::ostringstream os;
      os << table.source() << ":" << table.LineOf(r) << ": column \"" << column
         << "\" is empty; every observation needs a group label";
      throw std::runtime_error(os.str());
    }
    labels.push_back(text);
  }
  return labels;
}

StatsInput ReadInput(const StatsArgs& a) {
  const io::CsvTable table = io::CsvTable::Read(a.csv_path);
  StatsInput in;
  in.source = table.source();
  const std::size_t response = table.Column(a.response);
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < table.rows(); ++r) {
    if (NoValue(table.Text(r, response))) {
      in.left_out_lines.push_back(table.LineOf(r));
      continue;
    }
    in.response.push_back(table.Number(r, response));  // other text is an error naming the line
    rows.push_back(r);
  }
  in.factor = ReadLabels(table, a.factor, rows);
  if (!a.factor2.empty()) in.factor2 = ReadLabels(table, a.factor2, rows);
  if (table.rows() == 0) throw std::runtime_error(in.source + ": the table has no data rows");
  if (rows.empty())
    throw std::runtime_error(in.source + ": no row has a value of \"" + a.response +
                             "\" (every one is empty or nan)");
  return in;
}

/// "Left out: 2 rows without a value of mu_eff (lines 2, 5)\n", or nothing.
std::string LeftOutText(const StatsInput& in, const std::string& response) {
  if (in.left_out_lines.empty()) return "";
  std::ostringstream os;
  os << "Left out: " << in.left_out_lines.size() << " row(s) without a value of " << response
     << " (empty or nan), on line(s) ";
  for (std::size_t i = 0; i < in.left_out_lines.size() && i < 10; ++i)
    os << (i ? ", " : "") << in.left_out_lines[i];
  if (in.left_out_lines.size() > 10) os << ", ...";
  os << "\n";
  return os.str();
}

// ----------------------------------------------------------------------------------------

json RunCsv(const StatsArgs& a) {
  if (a.csv_path.empty())
    throw CLI::ValidationError("INPUT", "an input is required: a study file or a CSV table");
  if (a.response.empty() || a.factor.empty())
    throw CLI::ValidationError("--response/--factor",
                               "a CSV table needs --response COL and --factor COL");
  const StatsInput in = ReadInput(a);
  const std::string context = in.source + " (" + a.response + " by " + a.factor + "): ";
  stats::OneWayAnalysis analysis;
  std::optional<stats::TwoWayAnovaResult> two_way;
  try {
    stats::OneWayAnalysisOptions options;
    options.alpha = a.alpha;
    analysis = stats::AnalyzeOneWay(stats::GroupByLabel(in.response, in.factor), options);
    if (!a.factor2.empty()) {
      stats::TwoWayOptions o;
      o.type =
          a.ss_type == "I" ? stats::SumOfSquaresType::kTypeI : stats::SumOfSquaresType::kTypeIII;
      o.name_a = a.factor;
      o.name_b = a.factor2;
      two_way = stats::TwoWayAnova(in.response, in.factor, in.factor2, o);
    }
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(context + e.what());
  }
  if (!a.out_csv.empty()) study::WriteLongCsv(a.out_csv, analysis, two_way);
  if (a.json) {
    json j = {{"input",
               {{"csv", in.source},
                {"response", a.response},
                {"factor", a.factor},
                {"factor2", a.factor2.empty() ? json(nullptr) : json(a.factor2)},
                {"observations", in.response.size()},
                {"left_out_lines", in.left_out_lines},
                {"alpha", a.alpha}}}};
    j.update(study::OneWayJson(analysis.original, analysis.alpha));
    j["transform"] = study::TransformJson(analysis.transform, analysis.alpha);
    j["two_way"] = two_way ? study::TwoWayJson(*two_way) : json(nullptr);
    return j;
  }
  std::cout << LeftOutText(in, a.response);
  study::WriteOneWayAnalysisText(std::cout, a.response, a.factor, in.source, in.response.size(),
                                 analysis, two_way);
  if (!a.out_csv.empty()) std::cout << "Tables written to " << a.out_csv << "\n";
  return nullptr;
}

// ----------------------------------------------------------------------------------------
// Study mode: the paper's tables (docs/statistics.md, "The command") of a study file, computed
// and stored by hoof::study, shown here.
// ----------------------------------------------------------------------------------------

json RunStudy(const StatsArgs& a) {
  if (!a.csv_path.empty())
    throw CLI::ValidationError("INPUT/--csv", "give one input: a study file or a CSV table");
  if (!a.response.empty() || !a.factor.empty() || !a.factor2.empty())
    throw CLI::ValidationError("--response/--factor/--factor2",
                               "only for a CSV table; a study file is analysed for e and mu_eff "
                               "by surface, angle and speed");
  study::StatisticsOptions options;
  options.alpha = a.alpha;
  options.ss_type =
      a.ss_type == "I" ? stats::SumOfSquaresType::kTypeI : stats::SumOfSquaresType::kTypeIII;
  const study::StudyStatistics s =
      study::StoreStatistics(a.study_h5, options, a.out_csv, a.shown_as);
  if (a.json) return study::StudyStatisticsJson(s);
  PrintStudyStatistics(s, a.out_csv);
  return nullptr;
}

/// Whether `path` is meant as a study file, not a CSV table: named .h5 (or .hdf5), or HDF5 by
/// its signature. A .h5 file that is not HDF5 is then a bad study file, named as such.
bool IsHdf5(const std::string& path) {
  for (const char* ending : {".h5", ".hdf5", ".H5"})
    if (path.size() > std::strlen(ending) &&
        path.compare(path.size() - std::strlen(ending), std::string::npos, ending) == 0)
      return true;
  std::ifstream in(path, std::ios::binary);
  char signature[8] = {};
  in.read(signature, sizeof signature);
  return in.gcount() == 8 && std::string(signature, 8) == std::string("\x89HDF\r\n\x1a\n", 8);
}

void Run(StatsArgs a, RunState& state) {
  if (!(a.alpha > 0.0 && a.alpha < 1.0))
    throw CLI::ValidationError("--alpha", "must be in (0, 1), got " + std::to_string(a.alpha));
  if (a.ss_type != "I" && a.ss_type != "III")
    throw CLI::ValidationError("--ss-type", "must be I or III, got " + a.ss_type);
  if (!a.input.empty()) {
    if (!a.csv_path.empty())
      throw CLI::ValidationError("INPUT/--csv", "give one input: a study file or a CSV table");
    (IsHdf5(a.input) ? a.study_h5 : a.csv_path) = a.input;
  }
  const json results = !a.study_h5.empty() ? RunStudy(a) : RunCsv(a);
  state.exit_code = kExitOk;
  if (a.json) PrintEnvelope("stats", state.exit_code, results);
}

}  // namespace

void RegisterStats(CLI::App& app, RunState& state) {
  auto args = std::make_shared<StatsArgs>();
  CLI::App* cmd = app.add_subcommand(
      "stats",
      "One-way ANOVA of a response by a factor, with Bartlett, Welch, a Box-Cox transform when "
      "variances differ, and Fisher's LSD; two-way ANOVA with --factor2. With a study file: e "
      "and mu_eff by surface, angle and speed, stored under /stats");
  cmd->add_option("input", args->input,
                  "A study file from `hoofimpact analyze` or `run` (HDF5), or a CSV table with "
                  "a header row (needs --response and --factor)")
      ->check(CLI::ExistingFile);
  // --csv FILE, the earlier way to give a table: still works, not shown.
  cmd->add_option("--csv", args->csv_path, "Deprecated: give the table as INPUT")
      ->check(CLI::ExistingFile)
      ->group("");
  cmd->add_option("--response", args->response, "Column holding the response (numbers)");
  cmd->add_option("--factor", args->factor, "Column holding the group label of each row");
  cmd->add_option("--factor2", args->factor2, "Second factor: adds the two-way table");
  cmd->add_option("--alpha", args->alpha,
                  "Significance level for Bartlett (transform), ANOVA (LSD) and LSD pairs")
      ->capture_default_str();
  cmd->add_option("--ss-type", args->ss_type, "Two-way sums of squares: III or I (sequential)")
      ->capture_default_str();
  AddJsonFlag(cmd, args->json);
  cmd->add_option("--tables-csv", args->out_csv,
                  "Also write every table to this CSV (columns table,row,statistic,value)");
  // --out-csv, its earlier name: still works, not shown.
  cmd->add_option("--out-csv", args->out_csv, "Deprecated: --tables-csv")->group("");
  cmd->callback([args, &state] { Run(*args, state); });
}

void PrintStudyStatistics(const study::StudyStatistics& s, const std::string& out_csv) {
  study::WriteStudyStatisticsText(std::cout, s);
  std::cout << "\nTables stored in " << s.path << " under /stats"
            << (out_csv.empty() ? "" : " and written to " + out_csv) << "\n";
}

}  // namespace hoof::cli
