#include "discovery/discovery_tables.h"

#include <array>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

Table TestsTable(const std::string& name, const std::string& description,
                 const std::vector<StructureTest>& tests) {
  std::vector<std::string> quantity, scope, covariate, test, what;
  std::vector<double> statistic, df1, df2, p, p_holm;
  std::vector<std::int64_t> significant;
  for (const auto& t : tests) {
    quantity.push_back(t.quantity);
    scope.push_back(t.scope);
    covariate.push_back(t.covariate);
    test.push_back(t.test);
    statistic.push_back(t.statistic);
    df1.push_back(t.df1);
    df2.push_back(t.df2);
    p.push_back(t.p);
    p_holm.push_back(t.p_holm);
    significant.push_back(Flag(t.significant));
    what.push_back(t.description);
  }
  return Table{
      name,
      description,
      {Column::Texts("quantity", "v_x, v_y, w (residuals after impact) or marker_ratio", quantity),
       Column::Texts("scope", "surface name, or all", scope),
       Column::Texts("covariate", "what the residuals are tested against", covariate),
       Column::Texts("test", "the test against the noise model, e.g. slope z or mean t", test),
       Column::Numbers("statistic", "1", "z or t statistic", statistic),
       Column::Numbers("df1", "1", "degrees of freedom of a t test (NaN for z)", df1),
       Column::Numbers("df2", "1", "second degrees of freedom, when the test has them (NaN)", df2),
       Column::Numbers("p", "1", "p-value, unadjusted", p),
       Column::Numbers("p_holm", "1", "p-value, Holm-adjusted over every test of the round",
                       p_holm),
       Column::Integers("significant", "", "1 when p_holm < alpha", significant),
       Column::Texts("description", "the test in words", what)}};
}

Table CandidatesTable(const std::string& name, const std::vector<CandidateResult>& candidates) {
  std::vector<std::int64_t> rank, measurement, fitted, significant, df, wald_clear;
  std::vector<std::string> key, label, parameter, unit, message, form, ident, confounded, outcome,
      reason, influential;
  std::vector<double> estimate, se, lr, p, p_per_surface, aic, bic, cv, cv_current, density,
      density_current, cv_p, detection_limit, p_without;
  for (const auto& c : candidates) {
    rank.push_back(c.rank);
    key.push_back(c.key);
    label.push_back(c.name);
    parameter.push_back(c.parameter);
    unit.push_back(c.unit);
    measurement.push_back(Flag(c.measurement_effect));
    fitted.push_back(Flag(c.fitted));
    message.push_back(c.message);
    form.push_back(ToString(c.form));
    estimate.push_back(c.estimate);
    se.push_back(c.se);
    lr.push_back(c.lr_statistic);
    df.push_back(c.df);
    p.push_back(c.p_value);
    p_per_surface.push_back(c.p_per_surface);
    aic.push_back(c.delta_aic);
    bic.push_back(c.delta_bic);
    cv.push_back(c.cv_error);
    cv_current.push_back(c.cv_error_current);
    density.push_back(c.cv_density);
    density_current.push_back(c.cv_density_current);
    cv_p.push_back(c.cv_p);
    ident.push_back(ToString(c.identifiability));
    confounded.push_back(c.confounded_with);
    significant.push_back(Flag(c.significant));
    wald_clear.push_back(Flag(c.wald_clear));
    influential.push_back(c.influential_trial);
    p_without.push_back(c.p_without_influential);
    outcome.push_back(ToString(c.outcome));
    reason.push_back(c.reason);
    detection_limit.push_back(c.detection_limit);
  }
  const std::string outcomes = Choices(AllCandidateOutcomes());
  const std::string identifiabilities = Choices(std::array{
      Identifiability::kIdentified, Identifiability::kNotTested, Identifiability::kConfounded});
  return Table{
      name,
      "Every candidate effect of the round, fitted jointly with the per-surface parameters, in "
      "rank order (1 = added or strongest evidence); the values of each are in candidate_values",
      {Column::Integers("rank", "1", "1 = added or strongest evidence", rank),
       Column::Texts("key", "library key of the effect", key),
       Column::Texts("name", "the effect in words", label),
       Column::Texts("parameter", "its parameter", parameter),
       Column::Texts("unit", "unit of the parameter (of estimate, se and detection_limit)", unit),
       Column::Integers("measurement_effect", "",
                        "1 when it changes the image, not the physics (out-of-plane rotation)",
                        measurement),
       Column::Integers("fitted", "", "1 when the fit ran", fitted),
       Column::Texts("message", "why the fit did not run, or empty", message),
       Column::Texts("form", "the form the data chose: " + FormChoices(), form),
       Column::Numbers("estimate", kEstimateUnits,
                       "the shared value, or the largest surface value of a per-surface effect "
                       "(NaN when undefined)",
                       estimate),
       Column::Numbers("se", kEstimateUnits, "its standard error (NaN when undefined)", se),
       Column::Numbers("lr_statistic", "1",
                       "likelihood-ratio statistic against the current model under the noise "
                       "model",
                       lr),
       Column::Integers("df", "1",
                        "parameters the effect adds (boundary-corrected chi-bar-square with df "
                        "parameters at their lower bound 0)",
                        df),
       Column::Numbers("p_value", "1", "likelihood-ratio p-value", p),
       Column::Numbers("p_per_surface", "1",
                       "per-surface against shared values (chi-square, surfaces - 1 dof)",
                       p_per_surface),
       Column::Numbers("delta_aic", "1", "AIC of this model minus the current (< 0 is better)",
                       aic),
       Column::Numbers("delta_bic", "1", "BIC of this model minus the current (< 0 is better)",
                       bic),
       Column::Numbers("cv_error", kHeldOutErrorUnit,
                       "held-out error with this effect, each trial fitted without its fold", cv),
       Column::Numbers("cv_error_current", kHeldOutErrorUnit, "the same for the current model",
                       cv_current),
       Column::Numbers("cv_density", kHeldOutDensityUnit,
                       "held-out density with this effect under its own noise model, each trial "
                       "fitted without its fold; what a contact effect is judged by (NaN for an "
                       "out-of-plane candidate)",
                       density),
       Column::Numbers("cv_density_current", kHeldOutDensityUnit, "the same for the current model",
                       density_current),
       Column::Numbers("cv_p", "1",
                       "paired one-sided t test that the held-out score the candidate is judged "
                       "by fell (cv_density where finite, else cv_error)",
                       cv_p),
       Column::Texts("identifiability", identifiabilities, ident),
       Column::Texts("confounded_with", "baseline parameters that absorb it in the probe",
                     confounded),
       Column::Integers("wald_clear", "",
                        "1 when the estimate stands clear of 0 (of the smallest value the fit may "
                        "take, where that is above 0) by its s.e. at the naming level",
                        wald_clear),
       Column::Texts("influential_trial",
                     "the trial whose log-likelihood gains most from the effect (checked for a "
                     "contact effect whose evidence holds otherwise; empty when not checked)",
                     influential),
       Column::Numbers("p_without_influential", "1",
                       "likelihood-ratio p with the current model and the effect both refitted "
                       "without influential_trial (NaN when not checked)",
                       p_without),
       Column::Integers(
           "significant", "",
           "1 when p_value < alpha / candidates, wald_clear and the held-out score fell "
           "(cv_density where finite, else cv_error; for cv_density in a round after an added "
           "effect, significantly: cv_p < 0.05), and p_without_influential, where checked, "
           "below 0.01",
           significant),
       Column::Texts("outcome", "why it was or was not added: " + outcomes, outcome),
       Column::Texts("reason", "why it was or was not added, in words", reason),
       Column::Numbers("detection_limit", kEstimateUnits,
                       "smallest size these trials would detect at the naming level with 80 % "
                       "power (shared form; NaN when not computed)",
                       detection_limit)}};
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

Table GapTable(const std::string& name, const std::vector<GapTrial>& gap) {
  std::vector<std::string> id, surface;
  std::vector<double> angle, speed, gap_before, gap_after;
  std::vector<std::int64_t> fold;
  std::vector<double> before[3], after[3];
  for (const auto& g : gap) {
    id.push_back(g.id);
    surface.push_back(g.surface);
    angle.push_back(g.angle_deg);
    speed.push_back(g.speed_m_s);
    fold.push_back(g.fold);
    for (int k = 0; k < 3; ++k) {
      before[k].push_back(g.residual_before[k]);
      after[k].push_back(g.residual_after[k]);
    }
    gap_before.push_back(g.gap_before);
    gap_after.push_back(g.gap_after);
  }
  const char* what[3] = {"v_x (along the surface)", "v_y (normal)", "w d_EC"};
  const char* suffix[3] = {"v_x", "v_y", "w"};
  Table t{name,
          "Per held-out trial: residuals after impact (fractions of the impact speed) of the "
          "current model (before) and with the round's effect (after), each fitted without the "
          "trial's fold",
          {Column::Texts("id", "trial id", id), Column::Texts("surface", "surface", surface),
           Column::Numbers("angle_deg", "deg", "surface angle", angle),
           Column::Numbers("speed_m_s", "m/s", "impact speed", speed),
           Column::Integers("fold", "1", "cross-validation fold the trial was held out in", fold)}};
  for (int k = 0; k < 3; ++k)
    t.columns.push_back(Column::Numbers(std::string("residual_before_") + suffix[k], "1",
                                        std::string("measured - simulated ") + what[k] +
                                            " after impact / impact speed, current model",
                                        before[k]));
  for (int k = 0; k < 3; ++k)
    t.columns.push_back(Column::Numbers(std::string("residual_after_") + suffix[k], "1",
                                        std::string("measured - simulated ") + what[k] +
                                            " after impact / impact speed, with the effect",
                                        after[k]));
  t.columns.push_back(Column::Numbers(
      "gap_before", "1", "root mean square of the used components, current model", gap_before));
  t.columns.push_back(Column::Numbers(
      "gap_after", "1", "root mean square of the used components, with the effect", gap_after));
  return t;
}

Table SurfacesTable(const DiscoveryResult& r) {
  std::vector<std::string> model, surface;
  std::vector<double> zeta, zeta_se, mu, mu_se, k, zeta_sd, mu_sd;
  std::array<std::vector<double>, 3> measurement_sd;
  std::vector<std::int64_t> trials;
  for (const auto* fits : {&r.baseline, &r.final_model})
    for (const auto& f : *fits) {
      model.push_back(fits == &r.baseline ? "baseline" : "final");
      surface.push_back(f.surface);
      zeta.push_back(f.zeta);
      zeta_se.push_back(f.zeta_se);
      mu.push_back(f.mu);
      mu_se.push_back(f.mu_se);
      k.push_back(f.k_N_m);
      trials.push_back(f.trials);
      zeta_sd.push_back(f.zeta_sd);
      mu_sd.push_back(f.mu_sd);
      for (int c = 0; c < 3; ++c)
        measurement_sd[static_cast<std::size_t>(c)].push_back(f.measurement_sd[c]);
    }
  return Table{
      "surfaces",
      "The model per surface fitted to every used trial: the baseline (the paper's model) and "
      "the final model (with the accepted effects); k is not identified and stays the paper's. "
      "zeta_sd and mu_sd are the noise model's trial-to-trial scatter of the coefficients, "
      "measurement_sd_* its systematic measurement error on the surface",
      {Column::Texts("model", "baseline or final", model),
       Column::Texts("surface", "surface name", surface),
       Column::Numbers("zeta", "1", "damping ratio", zeta),
       Column::Numbers("zeta_se", "1", "its standard error", zeta_se),
       Column::Numbers("mu", "1", "friction coefficient", mu),
       Column::Numbers("mu_se", "1", "its standard error", mu_se),
       Column::Numbers("k_N_m", "N/m", "stiffness used (not identified)", k),
       Column::Integers("trials", "1", "trials fitted", trials),
       Column::Numbers("zeta_sd", "1", "s.d. of zeta from trial to trial", zeta_sd),
       Column::Numbers("mu_sd", "1", "s.d. of mu from trial to trial (NaN without oblique trials)",
                       mu_sd),
       Column::Numbers("measurement_sd_v_x", "1",
                       "systematic measurement s.d. of v_x on this surface beyond each trial's "
                       "s.e., fraction of the impact speed (NaN without oblique trials)",
                       measurement_sd[0]),
       Column::Numbers("measurement_sd_v_y", "1", "the same of v_y", measurement_sd[1]),
       Column::Numbers("measurement_sd_w", "1", "the same of w d_EC (NaN without oblique trials)",
                       measurement_sd[2])}};
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
  const auto quantity = t.Texts("quantity"), scope = t.Texts("scope"),
             covariate = t.Texts("covariate"), test = t.Texts("test"),
             what = t.Texts("description");
  const auto statistic = t.Numbers("statistic"), df1 = t.Numbers("df1"), df2 = t.Numbers("df2"),
             p = t.Numbers("p"), p_holm = t.Numbers("p_holm");
  const auto significant = t.Flags("significant");
  std::vector<StructureTest> out(t.rows());
  for (std::size_t i = 0; i < t.rows(); ++i) {
    auto& s = out[i];
    s.quantity = quantity[i];
    s.scope = scope[i];
    s.covariate = covariate[i];
    s.test = test[i];
    s.statistic = statistic[i];
    s.df1 = df1[i];
    s.df2 = df2[i];
    s.p = p[i];
    s.p_holm = p_holm[i];
    s.significant = significant[i];
    s.description = what[i];
  }
  return out;
}

std::vector<CandidateResult> ReadCandidates(const std::filesystem::path& h5,
                                            const std::string& table) {
  const Reader t(h5, table);
  const auto rank = t.Integers("rank");
  const auto key = t.Texts("key"), label = t.Texts("name"), parameter = t.Texts("parameter"),
             unit = t.Texts("unit"), message = t.Texts("message"),
             confounded = t.Texts("confounded_with"), reason = t.Texts("reason");
  const auto form = t.Enums("form", &EffectFormFromString);
  const auto ident = t.Enums("identifiability", &IdentifiabilityFromString);
  const auto outcome = t.Enums("outcome", &CandidateOutcomeFromString);
  const auto measurement = t.Flags("measurement_effect"), fitted = t.Flags("fitted"),
             significant = t.Flags("significant"), wald_clear = t.Flags("wald_clear");
  const auto df = t.Integers("df");
  const auto estimate = t.Numbers("estimate"), se = t.Numbers("se"), lr = t.Numbers("lr_statistic"),
             p = t.Numbers("p_value"), p_per_surface = t.Numbers("p_per_surface"),
             aic = t.Numbers("delta_aic"), bic = t.Numbers("delta_bic"), cv = t.Numbers("cv_error"),
             cv_current = t.Numbers("cv_error_current"), cv_p = t.Numbers("cv_p"),
             detection_limit = t.Numbers("detection_limit");
  // Study files written before the held-out density was stored have none (NaN: judged by the
  // held-out error, as they were).
  std::vector<double> density(t.rows(), core::kNaN), density_current(t.rows(), core::kNaN);
  if (t.Has("cv_density"))
    density = t.Numbers("cv_density"), density_current = t.Numbers("cv_density_current");
  // Study files written before the influential-trial check have none (not checked).
  std::vector<std::string> influential(t.rows());
  std::vector<double> p_without(t.rows(), core::kNaN);
  if (t.Has("influential_trial"))
    influential = t.Texts("influential_trial"), p_without = t.Numbers("p_without_influential");
  std::vector<CandidateResult> out(t.rows());
  for (std::size_t i = 0; i < t.rows(); ++i) {
    auto& c = out[i];
    c.rank = static_cast<int>(rank[i]);
    c.key = key[i];
    c.name = label[i];
    c.parameter = parameter[i];
    c.unit = unit[i];
    c.measurement_effect = measurement[i];
    c.fitted = fitted[i];
    c.message = message[i];
    c.form = form[i];
    c.estimate = estimate[i];
    c.se = se[i];
    c.lr_statistic = lr[i];
    c.df = static_cast<int>(df[i]);
    c.p_value = p[i];
    c.p_per_surface = p_per_surface[i];
    c.delta_aic = aic[i];
    c.delta_bic = bic[i];
    c.cv_error = cv[i];
    c.cv_error_current = cv_current[i];
    c.cv_density = density[i];
    c.cv_density_current = density_current[i];
    c.cv_p = cv_p[i];
    c.identifiability = ident[i];
    c.confounded_with = confounded[i];
    c.significant = significant[i];
    c.wald_clear = wald_clear[i];
    c.influential_trial = influential[i];
    c.p_without_influential = p_without[i];
    c.outcome = outcome[i];
    c.reason = reason[i];
    c.detection_limit = detection_limit[i];
  }
  return out;
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
  const auto id = t.Texts("id"), surface = t.Texts("surface");
  const auto angle = t.Numbers("angle_deg"), speed = t.Numbers("speed_m_s"),
             gap_before = t.Numbers("gap_before"), gap_after = t.Numbers("gap_after");
  const auto fold = t.Integers("fold");
  const char* suffix[3] = {"v_x", "v_y", "w"};
  std::vector<double> before[3], after[3];
  for (int k = 0; k < 3; ++k) {
    before[k] = t.Numbers(std::string("residual_before_") + suffix[k]);
    after[k] = t.Numbers(std::string("residual_after_") + suffix[k]);
  }
  std::vector<GapTrial> out(t.rows());
  for (std::size_t i = 0; i < t.rows(); ++i) {
    auto& g = out[i];
    g.id = id[i];
    g.surface = surface[i];
    g.angle_deg = angle[i];
    g.speed_m_s = speed[i];
    g.fold = static_cast<int>(fold[i]);
    for (int k = 0; k < 3; ++k) {
      g.residual_before[k] = before[k][i];
      g.residual_after[k] = after[k][i];
    }
    g.gap_before = gap_before[i];
    g.gap_after = gap_after[i];
  }
  return out;
}

}  // namespace

std::vector<Table> DiscoveryTables(const DiscoveryResult& r) {
  std::vector<Table> tables;
  tables.push_back(Table{
      "summary",
      "The discovery workflow's outcome (hoofimpact discover; docs/discovery.md)",
      {Column::Integers("success", "", "1 when the workflow ran", {Flag(r.success)}),
       Column::Texts("message", "why it could not run, or empty", {r.message}),
       Column::Integers("trials_used", "1", "measured trials analysed", {r.trials_used}),
       Column::Integers("trials_skipped", "1", "trials skipped (not measured)", {r.trials_skipped}),
       Column::Integers("unexplained", "",
                        "1 when a significant disagreement remains with the final model",
                        {Flag(r.unexplained)}),
       Column::Numbers("seconds", "s", "wall-clock time of the workflow", {r.seconds}),
       Column::Integers("simulations", "1", "impacts simulated", {r.simulations}),
       Column::Integers("rounds", "1", "rounds run (tables rounds/1 ... rounds/<n>)",
                        {static_cast<std::int64_t>(r.rounds.size())}),
       Column::Texts("verdict", "the verdict in plain language", {r.verdict}),
       Column::Numbers("measurement_sd_v_x", "1",
                       "systematic measurement error (s.d.) of v_x after impact, fraction of the "
                       "impact speed (final noise model)",
                       {r.measurement_sd.x()}),
       Column::Numbers("measurement_sd_v_y", "1", "the same of v_y", {r.measurement_sd.y()}),
       Column::Numbers("measurement_sd_w", "1", "the same of w d_EC", {r.measurement_sd.z()})}});
  tables.push_back(SurfacesTable(r));
  {
    std::vector<std::string> key, surface, parameter, unit;
    std::vector<double> value, se;
    for (const auto& e : r.effects) {
      const auto [p, u] = ParameterOf(r, e.key);
      key.push_back(e.key);
      surface.push_back(e.surface);
      parameter.push_back(p);
      unit.push_back(u);
      value.push_back(e.value);
      se.push_back(e.se);
    }
    tables.push_back(Table{
        "effects",
        "The final model's effects beyond the paper's model, with their values: one row "
        "per value (a per-surface effect has one per surface)",
        {Column::Texts("key", "library key of the effect", key),
         Column::Texts("surface", "surface the value holds on; empty = all surfaces", surface),
         Column::Texts("parameter", "its parameter", parameter),
         Column::Texts("unit", "unit of value and se", unit),
         Column::Numbers("value", kEstimateUnits, "value in the final model", value),
         Column::Numbers("se", kEstimateUnits, "its standard error", se)}});
  }
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const Round& round = r.rounds[i];
    const std::string prefix = "rounds/" + std::to_string(i + 1) + "/";
    tables.push_back(Table{
        prefix + "summary",
        "What round " + std::to_string(i + 1) + " decided, and the held-out gap",
        {Column::Integers("index", "1", "round number", {round.index}),
         Column::Texts("accepted", "key of the effect added, empty when none", {round.accepted}),
         Column::Texts("decision", "the decision in words", {round.decision}),
         Column::Numbers("naming_level", "1",
                         "level per hypothesis at which the smallest p of the round's hypotheses "
                         "falls below it with probability alpha under the current model (min-P)",
                         {round.naming_level}),
         Column::Numbers("bonferroni_level", "1",
                         "alpha / tests (the hypotheses and the further directions of their "
                         "changes a search over sizes tries), for comparison",
                         {round.bonferroni_level}),
         Column::Integers("hypotheses", "1", "candidates x forms tried", {round.hypotheses}),
         Column::Numbers("gap_before", "1",
                         "held-out gap (root mean square over trials and components, fractions "
                         "of the impact speed), current model",
                         {round.gap_before}),
         Column::Numbers("gap_after", "1", "the same with the accepted effect", {round.gap_after}),
         Column::Numbers("gap_shrink", "1", "fraction by which the held-out gap shrank",
                         {round.gap_shrink})}});
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
    std::vector<std::string> key, label, parameter, unit, status, form, surfaces, partner,
        separating;
    std::vector<double> estimate, se, shrink;
    std::vector<ValuesOf> values;
    for (const auto& f : r.findings) {
      key.push_back(f.key);
      label.push_back(f.name);
      parameter.push_back(f.parameter);
      unit.push_back(f.unit);
      status.push_back(ToString(f.status));
      form.push_back(ToString(f.form));
      surfaces.push_back(JoinSurfaces(f.surfaces));
      values.push_back({&f.values, f.unit});
      estimate.push_back(f.estimate);
      se.push_back(f.se);
      partner.push_back(f.partner);
      separating.push_back(f.separating_measurement);
      shrink.push_back(f.gap_shrink);
    }
    tables.push_back(Table{
        "findings",
        "What the verdict says about each effect: named, tentative or indistinguishable",
        {Column::Texts("key", "library key of the effect", key),
         Column::Texts("name", "the effect in words", label),
         Column::Texts("parameter", "its parameter", parameter),
         Column::Texts("unit", "unit of estimate and se", unit),
         Column::Texts("status",
                       Choices(std::array{FindingStatus::kNamed, FindingStatus::kTentative,
                                          FindingStatus::kIndistinguishable}),
                       status),
         Column::Texts("form", FormChoices(), form),
         Column::Texts("surfaces",
                       "surfaces it was found on, joined with ','; empty for a shared effect",
                       surfaces),
         Column::Numbers("estimate", kEstimateUnits,
                         "shared value, or the largest surface value (all in finding_values)",
                         estimate),
         Column::Numbers("se", kEstimateUnits, "its standard error", se),
         Column::Texts("partner", "what it cannot be told apart from", partner),
         Column::Texts("separating_measurement", "what would separate them", separating),
         Column::Numbers("gap_shrink", "1", "held-out gap shrink when it was added", shrink)}});
    tables.push_back(ValuesTable("finding_values", "Every value of each finding's effect",
                                 "finding", "row of the finding in findings (0-based)", values));
  }
  tables.push_back(TestsTable("remaining",
                              "The significant disagreements the final model leaves (no rows: "
                              "none)",
                              r.remaining));
  {
    std::vector<std::string> id, surface;
    std::vector<double> angle, speed, ratio;
    std::vector<double> base[3], fin[3];
    for (const auto& t : r.residuals) {
      id.push_back(t.id);
      surface.push_back(t.surface);
      angle.push_back(t.angle_deg);
      speed.push_back(t.speed_m_s);
      for (int k = 0; k < 3; ++k) {
        base[k].push_back(t.baseline[k]);
        fin[k].push_back(t.final_model[k]);
      }
      ratio.push_back(t.marker_ratio);
    }
    const char* suffix[3] = {"v_x", "v_y", "w"};
    const char* what[3] = {"v_x (along the surface)", "v_y (normal)", "w d_EC"};
    Table t{"residuals",
            "Per used trial: residuals after impact (measured - simulated, fractions of the "
            "impact speed) under the baseline and the final model, fitted to every trial",
            {Column::Texts("id", "trial id", id), Column::Texts("surface", "surface", surface),
             Column::Numbers("angle_deg", "deg", "surface angle", angle),
             Column::Numbers("speed_m_s", "m/s", "impact speed", speed)}};
    for (int k = 0; k < 3; ++k)
      t.columns.push_back(Column::Numbers(std::string("baseline_") + suffix[k], "1",
                                          std::string("residual of ") + what[k] + ", baseline",
                                          base[k]));
    for (int k = 0; k < 3; ++k)
      t.columns.push_back(Column::Numbers(std::string("final_") + suffix[k], "1",
                                          std::string("residual of ") + what[k] + ", final model",
                                          fin[k]));
    t.columns.push_back(Column::Numbers(
        "marker_ratio", "1", "mean projected / layout marker distance after impact", ratio));
    tables.push_back(std::move(t));
  }
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
    if (t.rows() != 1)
      throw std::runtime_error(h5.string() + ": table " + kDiscoveryGroup + "/summary has " +
                               std::to_string(t.rows()) + " rows, not 1");
    r.success = t.Flags("success")[0];
    r.message = t.Texts("message")[0];
    r.trials_used = static_cast<int>(t.Integers("trials_used")[0]);
    r.trials_skipped = static_cast<int>(t.Integers("trials_skipped")[0]);
    r.unexplained = t.Flags("unexplained")[0];
    r.seconds = t.Numbers("seconds")[0];
    r.simulations = static_cast<long long>(t.Integers("simulations")[0]);
    rounds = t.Integers("rounds")[0];
    r.verdict = t.Texts("verdict")[0];
    r.measurement_sd = {t.Numbers("measurement_sd_v_x")[0], t.Numbers("measurement_sd_v_y")[0],
                        t.Numbers("measurement_sd_w")[0]};
  }
  {
    const Reader t(h5, "surfaces");
    const auto model = t.Texts("model"), surface = t.Texts("surface");
    const auto zeta = t.Numbers("zeta"), zeta_se = t.Numbers("zeta_se"), mu = t.Numbers("mu"),
               mu_se = t.Numbers("mu_se"), k = t.Numbers("k_N_m"), zeta_sd = t.Numbers("zeta_sd"),
               mu_sd = t.Numbers("mu_sd");
    const auto trials = t.Integers("trials");
    // Study files written before the measurement error was per surface have none (NaN).
    std::array<std::vector<double>, 3> measurement_sd;
    if (t.Has("measurement_sd_v_x"))
      measurement_sd = {t.Numbers("measurement_sd_v_x"), t.Numbers("measurement_sd_v_y"),
                        t.Numbers("measurement_sd_w")};
    for (std::size_t i = 0; i < t.rows(); ++i) {
      SurfaceFit f;
      for (int c = 0; c < 3; ++c)
        if (!measurement_sd[0].empty())
          f.measurement_sd[c] = measurement_sd[static_cast<std::size_t>(c)][i];
      f.surface = surface[i];
      f.zeta = zeta[i];
      f.zeta_se = zeta_se[i];
      f.mu = mu[i];
      f.mu_se = mu_se[i];
      f.k_N_m = k[i];
      f.trials = static_cast<int>(trials[i]);
      f.zeta_sd = zeta_sd[i];
      f.mu_sd = mu_sd[i];
      (model[i] == "baseline" ? r.baseline : r.final_model).push_back(f);
    }
  }
  {
    const Reader t(h5, "effects");
    const auto key = t.Texts("key"), surface = t.Texts("surface");
    const auto value = t.Numbers("value"), se = t.Numbers("se");
    for (std::size_t i = 0; i < t.rows(); ++i)
      r.effects.push_back(EffectValue{key[i], surface[i], value[i], se[i]});
  }
  for (std::int64_t n = 1; n <= rounds; ++n) {
    const std::string prefix = "rounds/" + std::to_string(n) + "/";
    Round round;
    {
      const Reader t(h5, prefix + "summary");
      if (t.rows() != 1)
        throw std::runtime_error(h5.string() + ": table " + kDiscoveryGroup + "/" + prefix +
                                 "summary has " + std::to_string(t.rows()) + " rows, not 1");
      round.index = static_cast<int>(t.Integers("index")[0]);
      round.accepted = t.Texts("accepted")[0];
      round.decision = t.Texts("decision")[0];
      round.naming_level = t.Numbers("naming_level")[0];
      round.bonferroni_level = t.Numbers("bonferroni_level")[0];
      round.hypotheses = static_cast<int>(t.Integers("hypotheses")[0]);
      round.gap_before = t.Numbers("gap_before")[0];
      round.gap_after = t.Numbers("gap_after")[0];
      round.gap_shrink = t.Numbers("gap_shrink")[0];
    }
    round.tests = ReadTests(h5, prefix + "tests");
    round.candidates = ReadCandidates(h5, prefix + "candidates");
    ReadValues(h5, prefix + "candidate_values", "candidate", round.candidates);
    round.gap = ReadGap(h5, prefix + "gap");
    r.rounds.push_back(std::move(round));
  }
  {
    const Reader t(h5, "findings");
    const auto key = t.Texts("key"), label = t.Texts("name"), parameter = t.Texts("parameter"),
               unit = t.Texts("unit"), surfaces = t.Texts("surfaces"), partner = t.Texts("partner"),
               separating = t.Texts("separating_measurement");
    const auto status = t.Enums("status", &FindingStatusFromString);
    const auto form = t.Enums("form", &EffectFormFromString);
    const auto estimate = t.Numbers("estimate"), se = t.Numbers("se"),
               shrink = t.Numbers("gap_shrink");
    for (std::size_t i = 0; i < t.rows(); ++i) {
      Finding f;
      f.key = key[i];
      f.name = label[i];
      f.parameter = parameter[i];
      f.unit = unit[i];
      f.status = status[i];
      f.form = form[i];
      f.surfaces = SplitSurfaces(surfaces[i]);
      f.estimate = estimate[i];
      f.se = se[i];
      f.partner = partner[i];
      f.separating_measurement = separating[i];
      f.gap_shrink = shrink[i];
      r.findings.push_back(std::move(f));
    }
  }
  ReadValues(h5, "finding_values", "finding", r.findings);
  r.remaining = ReadTests(h5, "remaining");
  {
    const Reader t(h5, "residuals");
    const auto id = t.Texts("id"), surface = t.Texts("surface");
    const auto angle = t.Numbers("angle_deg"), speed = t.Numbers("speed_m_s"),
               ratio = t.Numbers("marker_ratio");
    const char* suffix[3] = {"v_x", "v_y", "w"};
    std::vector<double> base[3], fin[3];
    for (int k = 0; k < 3; ++k) {
      base[k] = t.Numbers(std::string("baseline_") + suffix[k]);
      fin[k] = t.Numbers(std::string("final_") + suffix[k]);
    }
    for (std::size_t i = 0; i < t.rows(); ++i) {
      TrialResiduals res;
      res.id = id[i];
      res.surface = surface[i];
      res.angle_deg = angle[i];
      res.speed_m_s = speed[i];
      for (int k = 0; k < 3; ++k) {
        res.baseline[k] = base[k][i];
        res.final_model[k] = fin[k][i];
      }
      res.marker_ratio = ratio[i];
      r.residuals.push_back(std::move(res));
    }
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
