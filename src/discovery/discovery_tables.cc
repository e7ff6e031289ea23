#include "discovery/discovery_tables.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace hoof::discovery {
namespace {

using studyfile::Column;
using studyfile::Table;

constexpr const char* kEstimateUnits = "see column unit";

std::int64_t Flag(bool b) { return b ? 1 : 0; }

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
       Column::Texts("test", "lack-of-fit F, slope t or mean t", test),
       Column::Numbers("statistic", "1", "F or t statistic", statistic),
       Column::Numbers("df1", "1", "degrees of freedom (numerator of F; the t test's)", df1),
       Column::Numbers("df2", "1", "denominator degrees of freedom of F", df2),
       Column::Numbers("p", "1", "p-value, unadjusted", p),
       Column::Numbers("p_holm", "1", "p-value, Holm-adjusted over every test of the round",
                       p_holm),
       Column::Integers("significant", "", "1 when p_holm < alpha", significant),
       Column::Texts("description", "the test in words", what)}};
}

Table CandidatesTable(const std::string& name, const std::vector<CandidateResult>& candidates) {
  std::vector<std::int64_t> rank, measurement, fitted, significant;
  std::vector<std::string> key, label, parameter, unit, message, ident, confounded;
  std::vector<double> estimate, se, lr, p, aic, bic, cv, cv_current, cv_p;
  for (const auto& c : candidates) {
    rank.push_back(c.rank);
    key.push_back(c.key);
    label.push_back(c.name);
    parameter.push_back(c.parameter);
    unit.push_back(c.unit);
    measurement.push_back(Flag(c.measurement_effect));
    fitted.push_back(Flag(c.fitted));
    message.push_back(c.message);
    estimate.push_back(c.estimate);
    se.push_back(c.se);
    lr.push_back(c.lr_statistic);
    p.push_back(c.p_value);
    aic.push_back(c.delta_aic);
    bic.push_back(c.delta_bic);
    cv.push_back(c.cv_error);
    cv_current.push_back(c.cv_error_current);
    cv_p.push_back(c.cv_p);
    ident.push_back(c.identifiability);
    confounded.push_back(c.confounded_with);
    significant.push_back(Flag(c.significant));
  }
  return Table{
      name,
      "Every candidate effect of the round, fitted jointly with the per-surface parameters, in "
      "rank order (1 = lowest held-out error)",
      {Column::Integers("rank", "1", "1 = lowest held-out error", rank),
       Column::Texts("key", "library key of the effect", key),
       Column::Texts("name", "the effect in words", label),
       Column::Texts("parameter", "its parameter", parameter),
       Column::Texts("unit", "unit of the parameter (of estimate and se)", unit),
       Column::Integers("measurement_effect", "",
                        "1 when it changes the image, not the physics (out-of-plane rotation)",
                        measurement),
       Column::Integers("fitted", "", "1 when the fit ran", fitted),
       Column::Texts("message", "why the fit did not run, or empty", message),
       Column::Numbers("estimate", kEstimateUnits, "fitted parameter (NaN when undefined)",
                       estimate),
       Column::Numbers("se", kEstimateUnits, "its standard error (NaN when undefined)", se),
       Column::Numbers("lr_statistic", "1",
                       "-2 log likelihood of the current model minus this one (chi-square, 1 dof)",
                       lr),
       Column::Numbers("p_value", "1", "likelihood-ratio p-value", p),
       Column::Numbers("delta_aic", "1", "AIC of this model minus the current (< 0 is better)",
                       aic),
       Column::Numbers("delta_bic", "1", "BIC of this model minus the current (< 0 is better)",
                       bic),
       Column::Numbers("cv_error", "1",
                       "held-out error: mean squared held-out residual in units of the training "
                       "fit's noise, with this effect",
                       cv),
       Column::Numbers("cv_error_current", "1", "the same for the current model", cv_current),
       Column::Numbers("cv_p", "1", "paired one-sided t test that the held-out error fell", cv_p),
       Column::Texts("identifiability",
                     "identified, not tested by these data, or indistinguishable from ...", ident),
       Column::Texts("confounded_with", "baseline parameters that absorb it in the probe",
                     confounded),
       Column::Integers("significant", "",
                        "1 when p_value < alpha / candidates and the held-out error fell",
                        significant)}};
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
  std::vector<double> zeta, zeta_se, mu, mu_se, k;
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
    }
  return Table{
      "surfaces",
      "The model per surface fitted to every used trial: the baseline (the paper's model) and "
      "the final model (with the accepted effects); k is not identified and stays the paper's",
      {Column::Texts("model", "baseline or final", model),
       Column::Texts("surface", "surface name", surface),
       Column::Numbers("zeta", "1", "damping ratio", zeta),
       Column::Numbers("zeta_se", "1", "its standard error", zeta_se),
       Column::Numbers("mu", "1", "friction coefficient", mu),
       Column::Numbers("mu_se", "1", "its standard error", mu_se),
       Column::Numbers("k_N_m", "N/m", "stiffness used (not identified)", k),
       Column::Integers("trials", "1", "trials fitted", trials)}};
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

 private:
  const Column& Find(const std::string& name) const {
    for (const auto& c : table_.columns)
      if (c.name == name) return c;
    throw Error(name, "is missing");
  }
  std::runtime_error Error(const std::string& column, const std::string& what) const {
    return std::runtime_error(h5_.string() + ": table " + path_ + ": column \"" + column + "\" " +
                              what);
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
             ident = t.Texts("identifiability"), confounded = t.Texts("confounded_with");
  const auto measurement = t.Flags("measurement_effect"), fitted = t.Flags("fitted"),
             significant = t.Flags("significant");
  const auto estimate = t.Numbers("estimate"), se = t.Numbers("se"), lr = t.Numbers("lr_statistic"),
             p = t.Numbers("p_value"), aic = t.Numbers("delta_aic"), bic = t.Numbers("delta_bic"),
             cv = t.Numbers("cv_error"), cv_current = t.Numbers("cv_error_current"),
             cv_p = t.Numbers("cv_p");
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
    c.estimate = estimate[i];
    c.se = se[i];
    c.lr_statistic = lr[i];
    c.p_value = p[i];
    c.delta_aic = aic[i];
    c.delta_bic = bic[i];
    c.cv_error = cv[i];
    c.cv_error_current = cv_current[i];
    c.cv_p = cv_p[i];
    c.identifiability = ident[i];
    c.confounded_with = confounded[i];
    c.significant = significant[i];
  }
  return out;
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
       Column::Texts("verdict", "the verdict in plain language", {r.verdict})}});
  tables.push_back(SurfacesTable(r));
  {
    std::vector<std::string> key, parameter, unit;
    std::vector<double> value;
    for (const auto& [k, v] : r.effects) {
      const auto [p, u] = ParameterOf(r, k);
      key.push_back(k);
      parameter.push_back(p);
      unit.push_back(u);
      value.push_back(v);
    }
    tables.push_back(
        Table{"effects",
              "The final model's effects beyond the paper's model, with their values",
              {Column::Texts("key", "library key of the effect", key),
               Column::Texts("parameter", "its parameter", parameter),
               Column::Texts("unit", "unit of the value", unit),
               Column::Numbers("value", kEstimateUnits, "value in the final model", value)}});
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
    tables.push_back(GapTable(prefix + "gap", round.gap));
  }
  {
    std::vector<std::string> key, label, parameter, unit, status, partner, separating;
    std::vector<double> estimate, se, shrink;
    for (const auto& f : r.findings) {
      key.push_back(f.key);
      label.push_back(f.name);
      parameter.push_back(f.parameter);
      unit.push_back(f.unit);
      status.push_back(f.status);
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
         Column::Texts("status", "named, tentative or indistinguishable", status),
         Column::Numbers("estimate", kEstimateUnits, "parameter value", estimate),
         Column::Numbers("se", kEstimateUnits, "its standard error", se),
         Column::Texts("partner", "what it cannot be told apart from", partner),
         Column::Texts("separating_measurement", "what would separate them", separating),
         Column::Numbers("gap_shrink", "1", "held-out gap shrink when it was added", shrink)}});
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
                       "candidate (Bonferroni)",
                       {o.alpha}),
       Column::Integers("folds", "1", "leave-trials-out folds", {o.folds}),
       Column::Integers("max_rounds", "1", "effects added at most", {o.max_rounds}),
       Column::Integers("jobs", "1", "threads (0 = all cores)", {o.jobs}),
       Column::Texts("candidates", "library keys tried, joined with ','; empty = all", {keys}),
       Column::Numbers("relative_tolerance", "1", "of the simulator during fits",
                       {o.relative_tolerance})}};
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
  }
  {
    const Reader t(h5, "surfaces");
    const auto model = t.Texts("model"), surface = t.Texts("surface");
    const auto zeta = t.Numbers("zeta"), zeta_se = t.Numbers("zeta_se"), mu = t.Numbers("mu"),
               mu_se = t.Numbers("mu_se"), k = t.Numbers("k_N_m");
    const auto trials = t.Integers("trials");
    for (std::size_t i = 0; i < t.rows(); ++i) {
      SurfaceFit f;
      f.surface = surface[i];
      f.zeta = zeta[i];
      f.zeta_se = zeta_se[i];
      f.mu = mu[i];
      f.mu_se = mu_se[i];
      f.k_N_m = k[i];
      f.trials = static_cast<int>(trials[i]);
      (model[i] == "baseline" ? r.baseline : r.final_model).push_back(f);
    }
  }
  {
    const Reader t(h5, "effects");
    const auto key = t.Texts("key");
    const auto value = t.Numbers("value");
    for (std::size_t i = 0; i < t.rows(); ++i) r.effects[key[i]] = value[i];
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
      round.gap_before = t.Numbers("gap_before")[0];
      round.gap_after = t.Numbers("gap_after")[0];
      round.gap_shrink = t.Numbers("gap_shrink")[0];
    }
    round.tests = ReadTests(h5, prefix + "tests");
    round.candidates = ReadCandidates(h5, prefix + "candidates");
    round.gap = ReadGap(h5, prefix + "gap");
    r.rounds.push_back(std::move(round));
  }
  {
    const Reader t(h5, "findings");
    const auto key = t.Texts("key"), label = t.Texts("name"), parameter = t.Texts("parameter"),
               unit = t.Texts("unit"), status = t.Texts("status"), partner = t.Texts("partner"),
               separating = t.Texts("separating_measurement");
    const auto estimate = t.Numbers("estimate"), se = t.Numbers("se"),
               shrink = t.Numbers("gap_shrink");
    for (std::size_t i = 0; i < t.rows(); ++i) {
      Finding f;
      f.key = key[i];
      f.name = label[i];
      f.parameter = parameter[i];
      f.unit = unit[i];
      f.status = status[i];
      f.estimate = estimate[i];
      f.se = se[i];
      f.partner = partner[i];
      f.separating_measurement = separating[i];
      f.gap_shrink = shrink[i];
      r.findings.push_back(std::move(f));
    }
  }
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
