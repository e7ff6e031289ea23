#include "discovery/discovery_tables.h"

#include <array>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "studyfile/table_archive.h"

namespace hoof::discovery {
namespace {

using studyfile::Column;
using studyfile::Table;

constexpr const char* kEstimateUnits = "see column unit";

std::int64_t Flag(bool b) { return b ? 1 : 0; }

/// Surface names joined with ',' (empty = none: a shared effect).
std::string JoinSurfaces(const std::vector<std::string>& surfaces) {
  std::string out;
  for (std::size_t i = 0; i < surfaces.size(); ++i) out += (i ? "," : "") + surfaces[i];
  return out;
}

/// The inverse of JoinSurfaces: "" is no surface.
std::vector<std::string> SplitSurfaces(const std::string& text) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    out.push_back(
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

/// "a, b or c" of the texts of every value of an enum, for column descriptions.
template <typename Values>
std::string Choices(const Values& values) {
  std::string out;
  std::size_t i = 0;
  for (auto v : values) {
    out += std::string(i == 0 ? "" : i + 1 == values.size() ? " or " : ", ") + ToString(v);
    ++i;
  }
  return out;
}

std::string FormChoices() {
  return Choices(std::array{EffectForm::kShared, EffectForm::kPerSurface});
}

// ---- writing ------------------------------------------------------------------------------

/// The columns of a structure test, declared once for writing and reading.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, StructureTest>
void Serialize(Archive& a, T& t) {
  a.Text("quantity", t.quantity, "v_x, v_y, w (residuals after impact) or marker_ratio");
  a.Text("scope", t.scope, "surface name, or all");
  a.Text("covariate", t.covariate, "what the residuals are tested against");
  a.Text("test", t.test, "the test against the noise model, e.g. slope z or mean t");
  a.Number("statistic", t.statistic, "1", "z or t statistic");
  a.Number("df1", t.df1, "1", "degrees of freedom of a t test (NaN for z)");
  a.Number("df2", t.df2, "1", "second degrees of freedom, when the test has them (NaN)");
  a.Number("p", t.p, "1", "p-value, unadjusted");
  a.Number("p_holm", t.p_holm, "1", "p-value, Holm-adjusted over every test of the round");
  a.Flag("significant", t.significant, "1 when p_holm < alpha");
  a.Text("description", t.description, "the test in words");
}

constexpr studyfile::EnumText<EffectForm> kFormText{&ToString, &EffectFormFromString};
constexpr studyfile::EnumText<Identifiability> kIdentifiabilityText{&ToString,
                                                                    &IdentifiabilityFromString};
constexpr studyfile::EnumText<CandidateOutcome> kOutcomeText{&ToString,
                                                             &CandidateOutcomeFromString};

/// The columns of a candidate, declared once for writing and reading (its values are in a
/// table of their own: ValuesTable).
template <class Archive, class C>
requires std::is_same_v<std::remove_const_t<C>, CandidateResult>
void Serialize(Archive& a, C& c) {
  using studyfile::Presence;
  a.Integer("rank", c.rank, "1", "1 = added or strongest evidence");
  a.Text("key", c.key, "library key of the effect");
  a.Text("name", c.name, "the effect in words");
  a.Text("parameter", c.parameter, "its parameter");
  a.Text("unit", c.unit, "unit of the parameter (of estimate, se and detection_limit)");
  a.Flag("measurement_effect", c.measurement_effect,
         "1 when it changes the image, not the physics (out-of-plane rotation)");
  a.Flag("fitted", c.fitted, "1 when the fit ran");
  a.Text("message", c.message, "why the fit did not run, or empty");
  a.Choice("form", c.form, kFormText, "the form the data chose: " + FormChoices());
  a.Number("estimate", c.estimate, kEstimateUnits,
           "the shared value, or the largest surface value of a per-surface effect (NaN when "
           "undefined)");
  a.Number("se", c.se, kEstimateUnits, "its standard error (NaN when undefined)");
  a.Number("lr_statistic", c.lr_statistic, "1",
           "likelihood-ratio statistic against the current model under the noise model");
  a.Integer("df", c.df, "1",
            "parameters the effect adds (boundary-corrected chi-bar-square with df parameters "
            "at their lower bound 0)");
  a.Number("p_value", c.p_value, "1", "likelihood-ratio p-value");
  a.Number("p_per_surface", c.p_per_surface, "1",
           "per-surface against shared values (chi-square, surfaces - 1 dof)");
  a.Number("delta_aic", c.delta_aic, "1", "AIC of this model minus the current (< 0 is better)");
  a.Number("delta_bic", c.delta_bic, "1", "BIC of this model minus the current (< 0 is better)");
  a.Number("cv_error", c.cv_error, kHeldOutErrorUnit,
           "held-out error with this effect, each trial fitted without its fold");
  a.Number("cv_error_current", c.cv_error_current, kHeldOutErrorUnit,
           "the same for the current model");
  // Study files written before the held-out density was stored have none (NaN: judged by the
  // held-out error, as they were).
  a.Number("cv_density", c.cv_density, kHeldOutDensityUnit,
           "held-out density with this effect under its own noise model, each trial fitted "
           "without its fold; what a contact effect is judged by (NaN for an out-of-plane "
           "candidate)",
           Presence::kAddedLater);
  a.Number("cv_density_current", c.cv_density_current, kHeldOutDensityUnit,
           "the same for the current model", Presence::kAddedLater);
  a.Number("cv_p", c.cv_p, "1",
           "paired one-sided t test that the held-out score the candidate is judged by fell "
           "(cv_density where finite, else cv_error)");
  a.Choice("identifiability", c.identifiability, kIdentifiabilityText,
           Choices(std::array{Identifiability::kIdentified, Identifiability::kNotTested,
                              Identifiability::kConfounded}));
  a.Text("confounded_with", c.confounded_with, "baseline parameters that absorb it in the probe");
  a.Flag("wald_clear", c.wald_clear,
         "1 when the estimate stands clear of 0 (of the smallest value the fit may take, where "
         "that is above 0) by its s.e. at the naming level");
  // Study files written before the influential-trial check have none (not checked).
  a.Text("influential_trial", c.influential_trial,
         "the trial whose log-likelihood gains most from the effect (checked for a contact "
         "effect whose evidence holds otherwise; empty when not checked)",
         Presence::kAddedLater);
  a.Number("p_without_influential", c.p_without_influential, "1",
           "likelihood-ratio p with the current model and the effect both refitted without "
           "influential_trial (NaN when not checked)",
           Presence::kAddedLater);
  a.Flag("significant", c.significant,
         "1 when p_value < alpha / candidates, wald_clear and the held-out score fell "
         "(cv_density where finite, else cv_error; for cv_density in a round after an added "
         "effect, significantly: cv_p < 0.05), and p_without_influential, where checked, below "
         "0.01");
  a.Choice("outcome", c.outcome, kOutcomeText,
           "why it was or was not added: " + Choices(AllCandidateOutcomes()));
  a.Text("reason", c.reason, "why it was or was not added, in words");
  a.Number("detection_limit", c.detection_limit, kEstimateUnits,
           "smallest size these trials would detect at the naming level with 80 % power (shared "
           "form; NaN when not computed)");
}

Table TestsTable(const std::string& name, const std::string& description,
                 const std::vector<StructureTest>& tests) {
  return studyfile::TableWriter::Of(name, description, tests,
                                    [](auto& a, const StructureTest& t) { Serialize(a, t); });
}

Table CandidatesTable(const std::string& name, const std::vector<CandidateResult>& candidates) {
  return studyfile::TableWriter::Of(
      name,
      "Every candidate effect of the round, fitted jointly with the per-surface parameters, in "
      "rank order (1 = added or strongest evidence); the values of each are in candidate_values",
      candidates, [](auto& a, const CandidateResult& c) { Serialize(a, c); });
}

/// The values of effects, one row per value: `owner` is the row of the candidate or finding
/// (0-based) in the table they belong to.
struct ValuesOf {
  const std::vector<EffectValue>* values;
  std::string unit;  ///< the owner's
};
Table ValuesTable(const std::string& name, const std::string& description, const std::string& owner,
                  const std::string& owner_description, const std::vector<ValuesOf>& owners) {
  std::vector<std::int64_t> row;
  std::vector<std::string> key, surface, unit;
  std::vector<double> value, se;
  for (std::size_t i = 0; i < owners.size(); ++i)
    for (const auto& v : *owners[i].values) {
      row.push_back(static_cast<std::int64_t>(i));
      key.push_back(v.key);
      surface.push_back(v.surface);
      unit.push_back(owners[i].unit);
      value.push_back(v.value);
      se.push_back(v.se);
    }
  return Table{
      name,
      description,
      {Column::Integers(owner, "1", owner_description, row),
       Column::Texts("key", "library key of the effect", key),
       Column::Texts("surface", "surface the value holds on; empty = all surfaces", surface),
       Column::Texts("unit", "unit of value and se (the owner's)", unit),
       Column::Numbers("value", kEstimateUnits, "the value", value),
       Column::Numbers("se", kEstimateUnits, "its standard error", se)}};
}

/// The columns of a held-out trial, declared once for writing and reading.
template <class Archive, class G>
requires std::is_same_v<std::remove_const_t<G>, GapTrial>
void Serialize(Archive& a, G& g) {
  a.Text("id", g.id, "trial id");
  a.Text("surface", g.surface, "surface");
  a.Number("angle_deg", g.angle_deg, "deg", "surface angle");
  a.Number("speed_m_s", g.speed_m_s, "m/s", "impact speed");
  a.Integer("fold", g.fold, "1", "cross-validation fold the trial was held out in");
  const char* what[3] = {"v_x (along the surface)", "v_y (normal)", "w d_EC"};
  const char* suffix[3] = {"v_x", "v_y", "w"};
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("residual_before_") + suffix[k], g.residual_before[k], "1",
             std::string("measured - simulated ") + what[k] +
                 " after impact / impact speed, current model");
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("residual_after_") + suffix[k], g.residual_after[k], "1",
             std::string("measured - simulated ") + what[k] +
                 " after impact / impact speed, with the effect");
  a.Number("gap_before", g.gap_before, "1",
           "root mean square of the used components, current model");
  a.Number("gap_after", g.gap_after, "1",
           "root mean square of the used components, with the effect");
}

Table GapTable(const std::string& name, const std::vector<GapTrial>& gap) {
  return studyfile::TableWriter::Of(
      name,
      "Per held-out trial: residuals after impact (fractions of the impact speed) of the "
      "current model (before) and with the round's effect (after), each fitted without the "
      "trial's fold",
      gap, [](auto& a, const GapTrial& g) { Serialize(a, g); });
}

/// A row of the surfaces table: which model, and its fit on one surface.
struct SurfaceRow {
  std::string model;  ///< "baseline" or "final"
  SurfaceFit fit;
};

template <class Archive, class Row>
requires std::is_same_v<std::remove_const_t<Row>, SurfaceRow>
void Serialize(Archive& a, Row& row) {
  using studyfile::Presence;
  auto& f = row.fit;
  a.Text("model", row.model, "baseline or final");
  a.Text("surface", f.surface, "surface name");
  a.Number("zeta", f.zeta, "1", "damping ratio");
  a.Number("zeta_se", f.zeta_se, "1", "its standard error");
  a.Number("mu", f.mu, "1", "friction coefficient");
  a.Number("mu_se", f.mu_se, "1", "its standard error");
  a.Number("k_N_m", f.k_N_m, "N/m", "stiffness used (not identified)");
  a.Integer("trials", f.trials, "1", "trials fitted");
  a.Number("zeta_sd", f.zeta_sd, "1", "s.d. of zeta from trial to trial");
  a.Number("mu_sd", f.mu_sd, "1", "s.d. of mu from trial to trial (NaN without oblique trials)");
  // Study files written before the measurement error was per surface have none (NaN).
  a.Number("measurement_sd_v_x", f.measurement_sd[0], "1",
           "systematic measurement s.d. of v_x on this surface beyond each trial's s.e., "
           "fraction of the impact speed (NaN without oblique trials)",
           Presence::kAddedLater);
  a.Number("measurement_sd_v_y", f.measurement_sd[1], "1", "the same of v_y",
           Presence::kAddedLater);
  a.Number("measurement_sd_w", f.measurement_sd[2], "1",
           "the same of w d_EC (NaN without oblique trials)", Presence::kAddedLater);
}

Table SurfacesTable(const DiscoveryResult& r) {
  std::vector<SurfaceRow> rows;
  for (const SurfaceFit& f : r.baseline) rows.push_back({"baseline", f});
  for (const SurfaceFit& f : r.final_model) rows.push_back({"final", f});
  return studyfile::TableWriter::Of(
      "surfaces",
      "The model per surface fitted to every used trial: the baseline (the paper's model) and "
      "the final model (with the accepted effects); k is not identified and stays the paper's. "
      "zeta_sd and mu_sd are the noise model's trial-to-trial scatter of the coefficients, "
      "measurement_sd_* its systematic measurement error on the surface",
      rows, [](auto& a, const SurfaceRow& row) { Serialize(a, row); });
}

/// The one-row summary of the workflow; `rounds` is the number of rounds (tables rounds/<n>).
template <class Archive, class R>
requires std::is_same_v<std::remove_const_t<R>, DiscoveryResult>
void SerializeSummary(Archive& a, R& r, std::int64_t& rounds) {
  a.Flag("success", r.success, "1 when the workflow ran");
  a.Text("message", r.message, "why it could not run, or empty");
  a.Integer("trials_used", r.trials_used, "1", "measured trials analysed");
  a.Integer("trials_skipped", r.trials_skipped, "1", "trials skipped (not measured)");
  a.Flag("unexplained", r.unexplained,
         "1 when a significant disagreement remains with the final model");
  a.Number("seconds", r.seconds, "s", "wall-clock time of the workflow");
  a.Integer("simulations", r.simulations, "1", "impacts simulated");
  a.Integer("rounds", rounds, "1", "rounds run (tables rounds/1 ... rounds/<n>)");
  a.Text("verdict", r.verdict, "the verdict in plain language");
  a.Number("measurement_sd_v_x", r.measurement_sd[0], "1",
           "systematic measurement error (s.d.) of v_x after impact, fraction of the impact "
           "speed (final noise model)");
  a.Number("measurement_sd_v_y", r.measurement_sd[1], "1", "the same of v_y");
  a.Number("measurement_sd_w", r.measurement_sd[2], "1", "the same of w d_EC");
}

/// What a round decided: its one-row summary table.
template <class Archive, class R>
requires std::is_same_v<std::remove_const_t<R>, Round>
void SerializeSummary(Archive& a, R& round) {
  a.Integer("index", round.index, "1", "round number");
  a.Text("accepted", round.accepted, "key of the effect added, empty when none");
  a.Text("decision", round.decision, "the decision in words");
  a.Number("naming_level", round.naming_level, "1",
           "level per hypothesis at which the smallest p of the round's hypotheses falls below "
           "it with probability alpha under the current model (min-P)");
  a.Number("bonferroni_level", round.bonferroni_level, "1",
           "alpha / tests (the hypotheses and the further directions of their changes a search "
           "over sizes tries), for comparison");
  a.Integer("hypotheses", round.hypotheses, "1", "candidates x forms tried");
  a.Number("gap_before", round.gap_before, "1",
           "held-out gap (root mean square over trials and components, fractions of the impact "
           "speed), current model");
  a.Number("gap_after", round.gap_after, "1", "the same with the accepted effect");
  a.Number("gap_shrink", round.gap_shrink, "1", "fraction by which the held-out gap shrank");
}

/// A row of the final model's effects: a value, and the parameter and unit it is a value of.
struct EffectRow {
  EffectValue value;
  std::string parameter, unit;
};

template <class Archive, class Row>
requires std::is_same_v<std::remove_const_t<Row>, EffectRow>
void Serialize(Archive& a, Row& row) {
  a.Text("key", row.value.key, "library key of the effect");
  a.Text("surface", row.value.surface, "surface the value holds on; empty = all surfaces");
  a.Text("parameter", row.parameter, "its parameter");
  a.Text("unit", row.unit, "unit of value and se");
  a.Number("value", row.value.value, kEstimateUnits, "value in the final model");
  a.Number("se", row.value.se, kEstimateUnits, "its standard error");
}

constexpr studyfile::EnumText<FindingStatus> kStatusText{&ToString, &FindingStatusFromString};

/// What the verdict says about an effect (its values are in a table of their own).
template <class Archive, class F>
requires std::is_same_v<std::remove_const_t<F>, Finding>
void Serialize(Archive& a, F& f) {
  a.Text("key", f.key, "library key of the effect");
  a.Text("name", f.name, "the effect in words");
  a.Text("parameter", f.parameter, "its parameter");
  a.Text("unit", f.unit, "unit of estimate and se");
  a.Choice("status", f.status, kStatusText,
           Choices(std::array{FindingStatus::kNamed, FindingStatus::kTentative,
                              FindingStatus::kIndistinguishable}));
  a.Choice("form", f.form, kFormText, FormChoices());
  const std::string surfaces_description =
      "surfaces it was found on, joined with ','; empty for a shared effect";
  if constexpr (std::remove_cvref_t<Archive>::kWriting) {
    a.Text("surfaces", JoinSurfaces(f.surfaces), surfaces_description);
  } else {
    std::string surfaces;
    a.Text("surfaces", surfaces, surfaces_description);
    f.surfaces = SplitSurfaces(surfaces);
  }
  a.Number("estimate", f.estimate, kEstimateUnits,
           "shared value, or the largest surface value (all in finding_values)");
  a.Number("se", f.se, kEstimateUnits, "its standard error");
  a.Text("partner", f.partner, "what it cannot be told apart from");
  a.Text("separating_measurement", f.separating_measurement, "what would separate them");
  a.Number("gap_shrink", f.gap_shrink, "1", "held-out gap shrink when it was added");
}

/// A used trial's residuals under the baseline and the final model.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, TrialResiduals>
void Serialize(Archive& a, T& t) {
  a.Text("id", t.id, "trial id");
  a.Text("surface", t.surface, "surface");
  a.Number("angle_deg", t.angle_deg, "deg", "surface angle");
  a.Number("speed_m_s", t.speed_m_s, "m/s", "impact speed");
  const char* suffix[3] = {"v_x", "v_y", "w"};
  const char* what[3] = {"v_x (along the surface)", "v_y (normal)", "w d_EC"};
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("baseline_") + suffix[k], t.baseline[k], "1",
             std::string("residual of ") + what[k] + ", baseline");
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("final_") + suffix[k], t.final_model[k], "1",
             std::string("residual of ") + what[k] + ", final model");
  a.Number("marker_ratio", t.marker_ratio, "1",
           "mean projected / layout marker distance after impact");
}

/// Parameter name and unit of an effect key, from the candidates and findings that name it.
std::pair<std::string, std::string> ParameterOf(const DiscoveryResult& r, const std::string& key) {
  for (const auto& f : r.findings)
    if (f.key == key) return {f.parameter, f.unit};
  for (const auto& round : r.rounds)
    for (const auto& c : round.candidates)
      if (c.key == key) return {c.parameter, c.unit};
  return {"", ""};
}

// ---- reading ------------------------------------------------------------------------------

/// One table of the file, with column access that names the file, the table and the column.
class Reader {
 public:
  Reader(const std::filesystem::path& h5, const std::string& table)
      : h5_(h5), path_(std::string(kDiscoveryGroup) + "/" + table) {
    try {
      table_ = studyfile::ReadTable(h5, path_);
    } catch (const std::exception& e) {
      const std::string what = e.what();
      throw std::runtime_error(what.find(h5.string()) != std::string::npos
                                   ? what
                                   : h5.string() + ": table " + path_ + ": " + what);
    }
    rows_ = table_.columns.empty() ? 0 : table_.columns.front().size();
  }

  std::size_t rows() const { return rows_; }
  const Table& table() const { return table_; }
  /// "<file>: table <path>", how errors name the table.
  std::string where() const { return h5_.string() + ": table " + path_; }

  std::vector<double> Numbers(const std::string& name) const {
    const auto& c = Find(name);
    if (const auto* d = std::get_if<std::vector<double>>(&c.values)) return *d;
    if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values))
      return std::vector<double>(i->begin(), i->end());
    throw Error(name, "is not numeric");
  }
  std::vector<std::int64_t> Integers(const std::string& name) const {
    const auto& c = Find(name);
    if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values)) return *i;
    if (const auto* d = std::get_if<std::vector<double>>(&c.values)) {
      std::vector<std::int64_t> out;
      for (double x : *d) out.push_back(static_cast<std::int64_t>(x));
      return out;
    }
    throw Error(name, "is not numeric");
  }
  bool Has(const std::string& name) const {
    for (const auto& c : table_.columns)
      if (c.name == name) return true;
    return false;
  }
  std::vector<bool> Flags(const std::string& name) const {
    std::vector<bool> out;
    for (auto i : Integers(name)) out.push_back(i != 0);
    return out;
  }
  std::vector<std::string> Texts(const std::string& name) const {
    const auto& c = Find(name);
    if (const auto* s = std::get_if<std::vector<std::string>>(&c.values)) return *s;
    throw Error(name, "is not text");
  }
  /// A text column of enum values, each read with `parse` (a FromString function).
  template <typename Enum>
  std::vector<Enum> Enums(const std::string& name, Enum (*parse)(const std::string&)) const {
    std::vector<Enum> out;
    const auto texts = Texts(name);
    for (std::size_t i = 0; i < texts.size(); ++i) {
      try {
        out.push_back(parse(texts[i]));
      } catch (const std::exception& e) {
        throw Error(name, "row " + std::to_string(i) + ": " + e.what());
      }
    }
    return out;
  }
  /// The error for a bad value of column `column`.
  std::runtime_error Error(const std::string& column, const std::string& what) const {
    return std::runtime_error(h5_.string() + ": table " + path_ + ": column \"" + column + "\" " +
                              what);
  }

 private:
  const Column& Find(const std::string& name) const {
    for (const auto& c : table_.columns)
      if (c.name == name) return c;
    throw Error(name, "is missing");
  }

  std::filesystem::path h5_;
  std::string path_;
  Table table_;
  std::size_t rows_ = 0;
};

std::vector<StructureTest> ReadTests(const std::filesystem::path& h5, const std::string& table) {
  const Reader t(h5, table);
  return studyfile::TableReader::Read<StructureTest>(
      t.table(), t.where(), [](auto& a, StructureTest& s) { Serialize(a, s); });
}

std::vector<CandidateResult> ReadCandidates(const std::filesystem::path& h5,
                                            const std::string& table) {
  const Reader t(h5, table);
  return studyfile::TableReader::Read<CandidateResult>(
      t.table(), t.where(), [](auto& a, CandidateResult& c) { Serialize(a, c); });
}

/// Reads a ValuesTable and appends each row's value to the `values` of its owner (`owner`
/// column: the row of `owners`).
template <typename Owner>
void ReadValues(const std::filesystem::path& h5, const std::string& table, const std::string& owner,
                std::vector<Owner>& owners) {
  const Reader t(h5, table);
  const auto row = t.Integers(owner);
  const auto key = t.Texts("key"), surface = t.Texts("surface");
  const auto value = t.Numbers("value"), se = t.Numbers("se");
  for (std::size_t i = 0; i < t.rows(); ++i) {
    if (row[i] < 0 || static_cast<std::size_t>(row[i]) >= owners.size())
      throw t.Error(owner, "row " + std::to_string(i) + ": " + std::to_string(row[i]) +
                               " is not a row of the " + std::to_string(owners.size()) +
                               " it refers to");
    owners[static_cast<std::size_t>(row[i])].values.push_back(
        EffectValue{key[i], surface[i], value[i], se[i]});
  }
}

std::vector<GapTrial> ReadGap(const std::filesystem::path& h5, const std::string& table) {
  const Reader t(h5, table);
  return studyfile::TableReader::Read<GapTrial>(t.table(), t.where(),
                                                [](auto& a, GapTrial& g) { Serialize(a, g); });
}

}  // namespace

std::vector<Table> DiscoveryTables(const DiscoveryResult& r) {
  std::vector<Table> tables;
  std::int64_t rounds = static_cast<std::int64_t>(r.rounds.size());
  tables.push_back(studyfile::TableWriter::OfOne(
      "summary", "The discovery workflow's outcome (hoofimpact discover; docs/discovery.md)", r,
      [&](auto& a, const DiscoveryResult& x) { SerializeSummary(a, x, rounds); }));
  tables.push_back(SurfacesTable(r));
  {
    std::vector<EffectRow> effects;
    for (const auto& e : r.effects) {
      const auto [parameter, unit] = ParameterOf(r, e.key);
      effects.push_back({e, parameter, unit});
    }
    tables.push_back(studyfile::TableWriter::Of(
        "effects",
        "The final model's effects beyond the paper's model, with their values: one row per "
        "value (a per-surface effect has one per surface)",
        effects, [](auto& a, const EffectRow& e) { Serialize(a, e); }));
  }
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const Round& round = r.rounds[i];
    const std::string prefix = "rounds/" + std::to_string(i + 1) + "/";
    tables.push_back(studyfile::TableWriter::OfOne(
        prefix + "summary",
        "What round " + std::to_string(i + 1) + " decided, and the held-out gap", round,
        [](auto& a, const Round& x) { SerializeSummary(a, x); }));
    tables.push_back(TestsTable(prefix + "tests",
                                "Tests of the current model's residuals for structure (Holm over "
                                "the round's tests)",
                                round.tests));
    tables.push_back(CandidatesTable(prefix + "candidates", round.candidates));
    std::vector<ValuesOf> values;
    for (const auto& c : round.candidates) values.push_back({&c.values, c.unit});
    tables.push_back(ValuesTable(prefix + "candidate_values",
                                 "Every value of each candidate's chosen form (one row for a "
                                 "shared effect, one per surface for a per-surface effect)",
                                 "candidate", "row of the candidate in candidates (0-based)",
                                 values));
    tables.push_back(GapTable(prefix + "gap", round.gap));
  }
  {
    std::vector<ValuesOf> values;
    for (const auto& f : r.findings) values.push_back({&f.values, f.unit});
    tables.push_back(studyfile::TableWriter::Of(
        "findings",
        "What the verdict says about each effect: named, tentative or indistinguishable",
        r.findings, [](auto& a, const Finding& f) { Serialize(a, f); }));
    tables.push_back(ValuesTable("finding_values", "Every value of each finding's effect",
                                 "finding", "row of the finding in findings (0-based)", values));
  }
  tables.push_back(TestsTable("remaining",
                              "The significant disagreements the final model leaves (no rows: "
                              "none)",
                              r.remaining));
  tables.push_back(studyfile::TableWriter::Of(
      "residuals",
      "Per used trial: residuals after impact (measured - simulated, fractions of the impact "
      "speed) under the baseline and the final model, fitted to every trial",
      r.residuals, [](auto& a, const TrialResiduals& t) { Serialize(a, t); }));
  return tables;
}

Table DiscoveryOptionsTable(const DiscoveryOptions& o) {
  std::string keys;
  for (const auto& k : o.candidates) keys += (keys.empty() ? "" : ",") + k;
  return Table{
      "options",
      "The settings the discovery workflow ran with",
      {Column::Numbers("alpha", "1",
                       "family-wise level of the structure tests (Holm) and of naming a "
                       "candidate (min-P over the candidates and forms)",
                       {o.alpha}),
       Column::Integers("folds", "1", "leave-trials-out folds", {o.folds}),
       Column::Integers("max_rounds", "1", "effects added at most", {o.max_rounds}),
       Column::Integers("jobs", "1", "threads (0 = all cores)", {o.jobs}),
       Column::Texts("candidates", "library keys tried, joined with ','; empty = all", {keys}),
       Column::Integers("per_surface", "",
                        "1 when a contact effect could take its own value on each surface",
                        {Flag(o.per_surface)}),
       Column::Numbers("relative_tolerance", "1", "of the simulator during fits",
                       {o.relative_tolerance}),
       Column::Numbers("marker_ratio_tolerance", "1",
                       "smallest departure of the marker distance ratio that counts",
                       {o.marker_ratio_tolerance}),
       Column::Numbers("measurement_floor", "1",
                       "lower bound of the systematic measurement error per velocity component, "
                       "fraction of the impact speed",
                       {o.measurement_floor}),
       Column::Numbers(
           "replicate_tolerance", "1",
           "part of a replicate cell's mean residual the lack-of-fit test ignores, fraction of the "
           "impact speed",
           {o.replicate_tolerance})}};
}

DiscoveryResult ReadDiscovery(const std::filesystem::path& h5) {
  DiscoveryResult r;
  std::int64_t rounds = 0;
  {
    const Reader t(h5, "summary");
    studyfile::TableReader::ReadOne(t.table(), t.where(), r, [&](auto& a, DiscoveryResult& x) {
      SerializeSummary(a, x, rounds);
    });
  }
  {
    const Reader t(h5, "surfaces");
    for (const SurfaceRow& row : studyfile::TableReader::Read<SurfaceRow>(
             t.table(), t.where(), [](auto&a, SurfaceRow&x) { Serialize(a, x); }))
      (row.model == "baseline" ? r.baseline : r.final_model).push_back(row.fit);
  }
  {
    const Reader t(h5, "effects");
    for (const EffectRow& row : studyfile::TableReader::Read<EffectRow>(
             t.table(), t.where(), [](auto&a, EffectRow&x) { Serialize(a, x); }))
      r.effects.push_back(row.value);
  }
  for (std::int64_t n = 1; n <= rounds; ++n) {
    const std::string prefix = "rounds/" + std::to_string(n) + "/";
    Round round;
    {
      const Reader t(h5, prefix + "summary");
      studyfile::TableReader::ReadOne(t.table(), t.where(), round,
                                      [](auto& a, Round& x) { SerializeSummary(a, x); });
    }
    round.tests = ReadTests(h5, prefix + "tests");
    round.candidates = ReadCandidates(h5, prefix + "candidates");
    ReadValues(h5, prefix + "candidate_values", "candidate", round.candidates);
    round.gap = ReadGap(h5, prefix + "gap");
    r.rounds.push_back(std::move(round));
  }
  {
    const Reader t(h5, "findings");
    r.findings = studyfile::TableReader::Read<Finding>(
        t.table(), t.where(), [](auto& a, Finding& f) { Serialize(a, f); });
  }
  ReadValues(h5, "finding_values", "finding", r.findings);
  r.remaining = ReadTests(h5, "remaining");
  {
    const Reader t(h5, "residuals");
    r.residuals = studyfile::TableReader::Read<TrialResiduals>(
        t.table(), t.where(), [](auto& a, TrialResiduals& x) { Serialize(a, x); });
  }
  return r;
}

bool HasDiscovery(const std::filesystem::path& h5) {
  try {
    studyfile::ReadTable(h5, std::string(kDiscoveryGroup) + "/summary");
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace hoof::discovery
