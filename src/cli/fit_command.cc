// hoofimpact fit: the contact law from normal-impact velocities, reported as what velocities
// can identify (zeta, with an interval) and what they cannot (k), with the valley shown.
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/json_output.h"
#include "dynamics/contact_fit.h"
#include "format/number_format.h"
#include "io/atomic_file.h"
#include "study/normal_impacts.h"

namespace hoof::cli {
namespace {

using dynamics::ContactFitSummary;

struct FitArgs {
  std::string csv_path;
  std::string before_col = "v_before_m_s";
  std::string after_col = "v_after_m_s";
  std::string group_col = "surface";
  dynamics::SpecimenParameters specimen;
  dynamics::ContactFitOptions fit;
  bool json = false;
  std::string valley_csv;
  std::vector<std::string> filters;  // COL=VALUE: keep only the rows where COL holds VALUE
};

/// Draws the paper's objective over (log k, b) in the terminal: darker is a smaller MPE, and
/// '*' marks the fitted valley. Rows are b (top = b_max), columns log k.
std::string AsciiMap(const ContactFitSummary& s, double mass_kg) {
  if (s.map_k_N_m.empty()) return "";
  const char* shades = "@%#*+=-:. ";  // '@' is the smallest error
  const int nk = static_cast<int>(s.map_k_N_m.size());
  const int nb = static_cast<int>(s.map_b_N_s_m.size());
  double lo = s.map_mpe_percent.minCoeff();
  const double hi = std::min(s.map_mpe_percent.maxCoeff(), lo + 50.0);
  std::ostringstream os;
  os << "  Mean percentage error over the paper's box (b up, log10 k across; '@' lowest, "
        "'o' = fitted zeta):\n";
  for (int j = nb - 1; j >= 0; j -= 2) {
    os << "  " << std::setw(6) << std::fixed << std::setprecision(0) << s.map_b_N_s_m[j] << " |";
    for (int i = 0; i < nk; ++i) {
      const double k = s.map_k_N_m[i];
      const double b_valley = dynamics::DampingForRatio(s.zeta, k, mass_kg);
      const double db = (s.map_b_N_s_m.back() - s.map_b_N_s_m.front()) / (nb - 1);
      if (std::abs(b_valley - s.map_b_N_s_m[j]) <= db) {
        os << 'o';
        continue;
      }
      const double f = std::clamp((s.map_mpe_percent(i, j) - lo) / (hi - lo + 1e-300), 0.0, 1.0);
      os << shades[static_cast<int>(f * 9.0 + 0.5)];
    }
    os << "\n";
  }
  os << "         +" << std::string(static_cast<std::size_t>(nk), '-') << "\n";
  os << "          k = " << std::scientific << std::setprecision(0) << s.map_k_N_m.front()
     << std::string(static_cast<std::size_t>(std::max(0, nk - 16)), ' ') << s.map_k_N_m.back()
     << " N/m\n";
  return os.str();
}

void PrintText(const std::string& group, const ContactFitSummary& s, double mass_kg) {
  using format::Kind;
  std::ostringstream os;
  os << "Contact-law fit" << (group.empty() ? "" : " for " + group) << " (" << s.n
     << " normal impacts)\n";
  if (!s.success) {
    os << "  failed: " << s.message << "\n";
    std::cout << os.str();
    return;
  }
  os << "  zeta = " << format::WithError(s.zeta, s.zeta_se, Kind::kCoefficient)
     << "  (95 % interval " << format::Interval(s.zeta_ci_low, s.zeta_ci_high, Kind::kCoefficient)
     << ")";
  os << "\n  e (normal, closed form) = " << format::Number(s.e_normal, Kind::kCoefficient)
     << "; mean |error| of rebound speed " << format::Number(s.mpe_percent, Kind::kError)
     << " %, rms " << format::Number(s.rms_percent, Kind::kError) << " %\n\n";
  os << "  The valley (best b for each k; every row fits the data about equally well):\n";
  os << "        k (N/m)      b (N s/m)     zeta     MPE (%)   contact (µs)  in paper's box\n";
  for (const auto& p : s.valley) {
    os << "    " << std::setw(11) << format::Number(p.k_N_m) << "  " << std::setw(11)
       << format::Number(p.b_N_s_m) << "  " << std::setw(8)
       << format::Number(p.zeta, Kind::kCoefficient) << "  " << std::setw(8)
       << format::Number(p.mpe_percent, Kind::kError) << "  " << std::setw(10)
       << format::Number(p.contact_duration_s * 1e6) << "    "
       << (p.within_bounds ? "yes" : "no (b > max)") << "\n";
  }
  os << "\n" << AsciiMap(s, mass_kg) << "\n";
  os << s.Explanation() << "\n";
  std::cout << os.str();
}

nlohmann::json SummaryJson(const std::string& group, const ContactFitSummary& s) {
  nlohmann::json valley = nlohmann::json::array();
  for (const auto& p : s.valley)
    valley.push_back({{"k_N_m", p.k_N_m},
                      {"b_N_s_m", p.b_N_s_m},
                      {"zeta", p.zeta},
                      {"mpe_percent", p.mpe_percent},
                      {"contact_duration_s", p.contact_duration_s},
                      {"within_bounds", p.within_bounds}});
  return {{"group", group},
          {"success", s.success},
          {"message", s.message},
          {"n", s.n},
          {"zeta", JsonNumber(s.zeta)},
          {"zeta_se", JsonNumber(s.zeta_se)},
          {"zeta_ci_low", JsonNumber(s.zeta_ci_low)},
          {"zeta_ci_high", JsonNumber(s.zeta_ci_high)},
          {"e_normal", JsonNumber(s.e_normal)},
          {"mpe_percent", JsonNumber(s.mpe_percent)},
          {"rms_percent", JsonNumber(s.rms_percent)},
          {"k_identified", false},
          {"valley", valley},
          {"valley_k_range_N_m", {s.valley_k_min_N_m, s.valley_k_max_N_m}},
          {"valley_mpe_spread_percent", s.valley_mpe_spread_percent},
          {"valley_zeta_spread", s.valley_zeta_spread},
          {"explanation", s.Explanation()}};
}

}  // namespace

void RegisterFit(CLI::App& app, RunState& state) {
  auto args = std::make_shared<FitArgs>();
  CLI::App* cmd = app.add_subcommand(
      "fit", "Fit the contact law to normal impacts: zeta with an interval, and the (k, b) valley");
  cmd->add_option("csv", args->csv_path,
                  "CSV with one normal impact per row (speeds of C normal to the surface)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--before-col", args->before_col, "Column of approach speeds (m/s)")
      ->capture_default_str();
  cmd->add_option("--after-col", args->after_col, "Column of rebound speeds (m/s)")
      ->capture_default_str();
  cmd->add_option("--group-col", args->group_col,
                  "Column that splits the impacts into separate fits (ignored if absent)")
      ->capture_default_str();
  AddSpecimenOptions(cmd, args->specimen);
  // The bounds of simulate's --k, --b and --gravity-m-s2: beyond them the fit's simulations
  // do not end (1e300 once failed deep inside the fit, naming the simulator's options).
  cmd->add_option("--k-min", args->fit.k_min_N_m, "Lower bound of k (N/m; 1 to 1e12)")
      ->check(InRange(1.0, 1e12, "N/m"))
      ->capture_default_str();
  cmd->add_option("--k-max", args->fit.k_max_N_m, "Upper bound of k (N/m; 1 to 1e12)")
      ->check(InRange(1.0, 1e12, "N/m"))
      ->capture_default_str();
  cmd->add_option("--b-max", args->fit.b_max_N_s_m, "Upper bound of b (N s/m; 0 to 1e9)")
      ->check(InRange(0.0, 1e9, "N s/m"))
      ->capture_default_str();
  cmd->add_option("--gravity-m-s2", args->fit.gravity_m_s2, "Gravity g (0 to 100)")
      ->check(InRange(0.0, 100.0, "m/s^2"))
      ->capture_default_str();
  cmd->add_option("--where", args->filters,
                  "Keep only rows where COL=VALUE (numeric or text), e.g. surface_angle_deg=0; "
                  "may be repeated");
  AddJsonFlag(cmd, args->json);
  cmd->add_option("--valley-csv", args->valley_csv,
                  "Write the objective over the (k, b) grid and the valley as CSV");

  cmd->callback([args, &state, cmd] {
    const FitArgs& a = *args;
    // The fit's bounds, in the options' names (k_min_N_m is --k-min).
    ValidateOptions(
        cmd, [&] { a.fit.Validate(); },
        {{"k_min_N_m", "--k-min"}, {"k_max_N_m", "--k-max"}, {"b_max_N_s_m", "--b-max"}});
    std::map<std::string, std::vector<dynamics::NormalImpact>> groups;
    try {
      groups =
          study::ReadNormalImpacts(a.csv_path, {a.before_col, a.after_col, a.group_col, a.filters});
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--where", e.what());
    }
    nlohmann::json out = nlohmann::json::array();
    std::vector<std::pair<std::string, ContactFitSummary>> fits;
    bool all_ok = true;
    for (const auto& [name, impacts] : groups) {
      const ContactFitSummary s = dynamics::FitNormalContact(impacts, a.specimen, a.fit);
      all_ok = all_ok && s.success;
      if (a.json) {
        out.push_back(SummaryJson(name, s));
      } else {
        PrintText(name, s, a.specimen.mass_kg);
        std::cout << "\n";
      }
      fits.emplace_back(name, s);
    }
    if (!a.valley_csv.empty()) {
      io::WriteTextAtomically(a.valley_csv, study::ValleyCsv(fits, a.specimen.mass_kg));
      if (!a.json) std::cout << "Objective map and valley written to " << a.valley_csv << "\n";
    }
    state.exit_code = all_ok ? kExitOk : kExitFailure;
    if (a.json) {
      std::vector<JsonError> errors;
      for (const auto& [name, s] : fits)
        if (!s.success)
          errors.push_back({"group " + name + ": " + s.message, "", a.csv_path, "", ""});
      PrintEnvelope("fit", state.exit_code,
                    {{"csv", a.csv_path}, {"valley_csv", a.valley_csv}, {"groups", out}}, errors);
    }
  });
}

}  // namespace hoof::cli
