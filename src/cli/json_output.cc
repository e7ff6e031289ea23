#include "cli/json_output.h"

#include <cstring>
#include <iostream>

#include "cli/common_options.h"
#include "compare/trial_comparison.h"
#include "core/frames.h"
#include "report/html_report.h"

namespace hoof::cli {

nlohmann::json ErrorJson(const JsonError& error) {
  nlohmann::json j = {{"message", error.message}};
  if (!error.option.empty()) j["option"] = error.option;
  if (!error.file.empty()) j["file"] = error.file;
  if (!error.trial.empty()) j["trial"] = error.trial;
  if (!error.field.empty()) j["field"] = error.field;
  return j;
}

JsonError ErrorFromMessage(const std::string& message) {
  JsonError error{message, {}, {}, {}, {}};
  // CLI11's checks of a positional input: "study_h5: File does not exist: x.h5".
  for (const char* missing :
       {"File does not exist: ", "Directory does not exist: ", "Path does not exist: "})
    if (const auto at = message.find(missing); at != std::string::npos) {
      error.file = message.substr(at + std::strlen(missing));
      return error;
    }
  const auto colon = message.find(": ");
  if (colon == std::string::npos || colon == 0) return error;
  std::string head = message.substr(0, colon);
  if (head.find(' ') != std::string::npos) return error;
  if (head[0] == '-') {
    error.option = head;
    return error;
  }
  // "file.csv:12" names the file (and its line).
  if (const auto line = head.find_last_of(':');
      line != std::string::npos && line + 1 < head.size() &&
      head.find_first_not_of("0123456789", line + 1) == std::string::npos)
    head.resize(line);
  if (head.find('/') != std::string::npos || head.find('.') != std::string::npos) error.file = head;
  return error;
}

nlohmann::json Envelope(const std::string& command, int exit_code, nlohmann::json results,
                        const std::vector<JsonError>& errors,
                        const std::vector<std::string>& warnings) {
  nlohmann::json error_list = nlohmann::json::array();
  for (const auto& e : errors) error_list.push_back(ErrorJson(e));
  return {{"format", "hoofimpact"},
          {"format_version", kJsonFormatVersion},
          {"version", kVersion},
          {"command", command},
          {"success", exit_code == 0},
          {"exit_code", exit_code},
          {"results", std::move(results)},
          {"warnings", warnings},
          {"errors", std::move(error_list)}};
}

nlohmann::json SurfaceModelJson(const compare::SurfaceModel& m) {
  return {{"surface", m.surface},
          {"success", m.success},
          {"message", m.message},
          {"normal_trials", m.normal_trials},
          {"oblique_trials", m.oblique_trials},
          {"zeta", JsonNumber(m.zeta_fit.zeta)},
          {"zeta_se", JsonNumber(m.zeta_fit.zeta_se)},
          {"zeta_ci_low", JsonNumber(m.zeta_fit.zeta_ci_low)},
          {"zeta_ci_high", JsonNumber(m.zeta_fit.zeta_ci_high)},
          // The reference mass's k and b, where the mass is unknown, are not the body's.
          {"k_N_m", JsonNumber(m.mass_known ? m.k_N_m : core::kNaN)},
          {"b_N_s_m", JsonNumber(m.mass_known ? m.b_N_s_m : core::kNaN)},
          {"mass_known", m.mass_known},
          {"mu", JsonNumber(m.mu)},
          {"mu_se", JsonNumber(m.mu_se)},
          {"mu_only_lower_bound", m.mu_only_lower_bound}};
}

nlohmann::json ReportJson(const report::HtmlReportSummary& s) {
  return {{"output", s.output.string()},
          {"bytes", s.bytes},
          {"trials", s.trials},
          {"figures", s.figures},
          {"replays", s.replays},
          {"discovery", s.discovery},
          {"notes", s.notes}};
}

void PrintEnvelope(const std::string& command, int exit_code, nlohmann::json results,
                   const std::vector<JsonError>& errors, const std::vector<std::string>& warnings) {
  // NaN and infinities never reach the text: the commands put them in as null (JsonNumber),
  // and nlohmann writes any left over as null too.
  std::cout << Envelope(command, exit_code, std::move(results), errors, warnings).dump(2) << "\n"
            << std::flush;
}

CLI::Option* AddJsonFlag(CLI::App* cmd, bool& json) {
  return cmd->add_flag("--json", json,
                       "Print one JSON object on stdout instead of the text: the envelope of "
                       "docs/cli.md (format, format_version, command, success, results, errors)");
}

std::string JsonCommandOf(int argc, const char* const* argv, const CLI::App& app) {
  std::string command;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    if (std::strcmp(arg, "--") == 0) break;
    if (command.empty()) {
      for (const CLI::App* sub : app.get_subcommands({}))
        if (sub->get_name() == arg) command = arg;
      continue;
    }
    if (std::strcmp(arg, "--json") == 0) json = true;
  }
  return json ? command : std::string();
}

}  // namespace hoof::cli
