#pragma once
/// @file
/// The columns of the study file's `/discovery` tables, declared once per row type (internal to
/// hoof::discovery): a Serialize() per struct, visited by studyfile::TableWriter in
/// discovery_tables.cc and by studyfile::TableReader in discovery_tables_read.cc. A column
/// added after files were written is marked Presence::kAddedLater, so older files still read.
#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "discovery/discovery.h"
#include "discovery/discovery_tables.h"
#include "studyfile/table_archive.h"

namespace hoof::discovery::schema {

using studyfile::Column;
using studyfile::Table;

inline constexpr const char* kEstimateUnits = "see column unit";

/// Surface names joined with ',' (empty = none: a shared effect).
inline std::string JoinSurfaces(const std::vector<std::string>& surfaces) {
  std::string out;
  for (std::size_t i = 0; i < surfaces.size(); ++i) out += (i ? "," : "") + surfaces[i];
  return out;
}

/// The inverse of JoinSurfaces: "" is no surface.
inline std::vector<std::string> SplitSurfaces(const std::string& text) {
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

inline std::string FormChoices() {
  return Choices(std::array{EffectForm::kShared, EffectForm::kPerSurface});
}

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

/// The settings the workflow ran with, the one row of the table `options`. per_surface and the
/// tolerances after relative_tolerance came in later versions (older files lack them).
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, DiscoveryOptions>
void Serialize(Archive& a, T& o) {
  constexpr auto kLater = studyfile::Presence::kAddedLater;
  a.Number("alpha", o.alpha, "1",
           "family-wise level of the structure tests (Holm) and of naming a candidate (min-P over "
           "the candidates and forms)");
  a.Integer("folds", o.folds, "1", "leave-trials-out folds");
  a.Integer("max_rounds", o.max_rounds, "1", "effects added at most");
  a.Integer("jobs", o.jobs, "1", "threads (0 = all cores)");
  const char* candidates = "library keys tried, joined with ','; empty = all";
  if constexpr (Archive::kWriting) {
    a.Text("candidates", JoinSurfaces(o.candidates), candidates);
  } else {
    std::string keys;
    a.Text("candidates", keys, candidates);
    o.candidates = SplitSurfaces(keys);
  }
  a.Flag("per_surface", o.per_surface,
         "1 when a contact effect could take its own value on each surface", kLater);
  a.Number("relative_tolerance", o.relative_tolerance, "1", "of the simulator during fits");
  a.Number("marker_ratio_tolerance", o.marker_ratio_tolerance, "1",
           "smallest departure of the marker distance ratio that counts", kLater);
  a.Number("measurement_floor", o.measurement_floor, "1",
           "lower bound of the systematic measurement error per velocity component, fraction of "
           "the impact speed",
           kLater);
  a.Number("replicate_tolerance", o.replicate_tolerance, "1",
           "part of a replicate cell's mean residual the lack-of-fit test ignores, fraction of the "
           "impact speed",
           kLater);
}

inline constexpr studyfile::EnumText<EffectForm> kFormText{&ToString, &EffectFormFromString};
inline constexpr studyfile::EnumText<Identifiability> kIdentifiabilityText{
    &ToString, &IdentifiabilityFromString};
inline constexpr studyfile::EnumText<CandidateOutcome> kOutcomeText{&ToString,
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

inline constexpr studyfile::EnumText<FindingStatus> kStatusText{&ToString,
                                                                &FindingStatusFromString};

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

/// The columns that name a trial in /discovery/residuals and /prediction/trials.
template <class Archive, class T>
void SerializeTrialKey(Archive& a, T& t) {
  a.Text("id", t.id, "trial id");
  a.Text("surface", t.surface, "surface");
  a.Number("angle_deg", t.angle_deg, "deg", "surface angle");
  a.Number("speed_m_s", t.speed_m_s, "m/s", "impact speed");
}

/// A used trial's residuals under the baseline and the final model.
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, TrialResiduals>
void Serialize(Archive& a, T& t) {
  SerializeTrialKey(a, t);
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

/// A trial's prediction z under the baseline model (group /prediction).
template <class Archive, class T>
requires std::is_same_v<std::remove_const_t<T>, TrialPrediction>
void Serialize(Archive& a, T& t) {
  SerializeTrialKey(a, t);
  const char* suffix[3] = {"v_x", "v_y", "w"};
  const char* what[3] = {"v_x (along the surface)", "v_y (normal)", "w d_EC"};
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("residual_") + suffix[k], t.residual[k], "1",
             std::string("measured - predicted ") + what[k] +
                 " after impact, baseline model, fraction of the impact speed");
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("prediction_sd_") + suffix[k], t.prediction_sd[k], "1",
             std::string("s.d. of a new trial's residual of ") + what[k] +
                 ": measurement error, trial-to-trial scatter of zeta and mu, systematic error, "
                 "error of the fitted zeta and mu");
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("t_") + suffix[k], t.t[k], "1",
             std::string("residual / prediction s.d. of ") + what[k]);
  a.Integer("dof", t.dof, "1",
            "degrees of freedom of t: the surface's other trials less its "
            "mean parameters");
  for (int k = 0; k < 3; ++k)
    a.Number(std::string("z_") + suffix[k], t.z[k], "1",
             std::string("normal z with the tail probability of t on dof, of ") + what[k]);
}

/// Parameter name and unit of an effect key, from the candidates and findings that name it.
/// A row of a values table (candidate_values, finding_values): one value of an effect, the row
/// of its owner (a candidate or a finding) in the owner's table, and the owner's unit.
struct ValueRow {
  std::int64_t owner = 0;
  EffectValue value;
  std::string unit;
};

/// `owner` names the owner column ("candidate" or "finding"), `owner_description` says what
/// its numbers are.
template <class Archive, class Row>
requires std::is_same_v<std::remove_const_t<Row>, ValueRow>
void Serialize(Archive& a, Row& row, const std::string& owner,
               const std::string& owner_description) {
  a.Integer(owner, row.owner, "1", owner_description);
  a.Text("key", row.value.key, "library key of the effect");
  a.Text("surface", row.value.surface, "surface the value holds on; empty = all surfaces");
  a.Text("unit", row.unit, "unit of value and se (the owner's)");
  a.Number("value", row.value.value, kEstimateUnits, "the value");
  a.Number("se", row.value.se, kEstimateUnits, "its standard error");
}

}  // namespace hoof::discovery::schema
