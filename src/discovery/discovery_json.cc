// The discovery result as JSON, as `hoofimpact discover --json` prints it (docs/discovery.md,
// "Output"): the same fields and names as the /discovery tables of the study file.
#include "discovery/discovery_json.h"

#include <cmath>

namespace hoof::discovery {
namespace {

using nlohmann::json;

/// A number, or null when it is not finite (JSON has no NaN).
json JsonNumber(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json Vector3(const Eigen::Vector3d& v) {
  return json::array({JsonNumber(v.x()), JsonNumber(v.y()), JsonNumber(v.z())});
}

json TestJson(const StructureTest& t) {
  return {{"quantity", t.quantity},
          {"scope", t.scope},
          {"covariate", t.covariate},
          {"test", t.test},
          {"statistic", JsonNumber(t.statistic)},
          {"df1", JsonNumber(t.df1)},
          {"df2", JsonNumber(t.df2)},
          {"p", JsonNumber(t.p)},
          {"p_holm", JsonNumber(t.p_holm)},
          {"significant", t.significant},
          {"description", t.description}};
}

json TestsJson(const std::vector<StructureTest>& tests) {
  json out = json::array();
  for (const auto& t : tests) out.push_back(TestJson(t));
  return out;
}

json ValuesJson(const std::vector<EffectValue>& values) {
  json out = json::array();
  for (const auto& v : values)
    out.push_back({{"key", v.key},
                   {"surface", v.surface},
                   {"value", JsonNumber(v.value)},
                   {"se", JsonNumber(v.se)}});
  return out;
}

json CandidateJson(const CandidateResult& c) {
  return {{"rank", c.rank},
          {"key", c.key},
          {"name", c.name},
          {"parameter", c.parameter},
          {"unit", c.unit},
          {"measurement_effect", c.measurement_effect},
          {"fitted", c.fitted},
          {"message", c.message},
          {"form", ToString(c.form)},
          {"estimate", JsonNumber(c.estimate)},
          {"se", JsonNumber(c.se)},
          {"values", ValuesJson(c.values)},
          {"lr_statistic", JsonNumber(c.lr_statistic)},
          {"df", c.df},
          {"p_value", JsonNumber(c.p_value)},
          {"p_per_surface", JsonNumber(c.p_per_surface)},
          {"delta_aic", JsonNumber(c.delta_aic)},
          {"delta_bic", JsonNumber(c.delta_bic)},
          {"cv_error", JsonNumber(c.cv_error)},
          {"cv_error_current", JsonNumber(c.cv_error_current)},
          {"cv_density", JsonNumber(c.cv_density)},
          {"cv_density_current", JsonNumber(c.cv_density_current)},
          {"cv_p", JsonNumber(c.cv_p)},
          {"identifiability", ToString(c.identifiability)},
          {"confounded_with", c.confounded_with},
          {"wald_clear", c.wald_clear},
          {"influential_trial", c.influential_trial},
          {"p_without_influential", JsonNumber(c.p_without_influential)},
          {"significant", c.significant},
          {"outcome", ToString(c.outcome)},
          {"reason", c.reason},
          {"detection_limit", JsonNumber(c.detection_limit)}};
}

json RoundJson(const Round& r) {
  json candidates = json::array(), gap = json::array();
  for (const auto& c : r.candidates) candidates.push_back(CandidateJson(c));
  for (const auto& g : r.gap)
    gap.push_back({{"id", g.id},
                   {"surface", g.surface},
                   {"angle_deg", JsonNumber(g.angle_deg)},
                   {"speed_m_s", JsonNumber(g.speed_m_s)},
                   {"fold", g.fold},
                   {"residual_before", Vector3(g.residual_before)},
                   {"residual_after", Vector3(g.residual_after)},
                   {"gap_before", JsonNumber(g.gap_before)},
                   {"gap_after", JsonNumber(g.gap_after)}});
  return {{"index", r.index},
          {"naming_level", JsonNumber(r.naming_level)},
          {"bonferroni_level", JsonNumber(r.bonferroni_level)},
          {"hypotheses", r.hypotheses},
          {"tests", TestsJson(r.tests)},
          {"candidates", candidates},
          {"accepted", r.accepted},
          {"decision", r.decision},
          {"gap", gap},
          {"gap_before", JsonNumber(r.gap_before)},
          {"gap_after", JsonNumber(r.gap_after)},
          {"gap_shrink", JsonNumber(r.gap_shrink)}};
}

json SurfacesJson(const std::vector<SurfaceFit>& fits) {
  json out = json::array();
  for (const auto& f : fits)
    out.push_back({{"surface", f.surface},
                   {"zeta", JsonNumber(f.zeta)},
                   {"zeta_se", JsonNumber(f.zeta_se)},
                   {"mu", JsonNumber(f.mu)},
                   {"mu_se", JsonNumber(f.mu_se)},
                   {"k_N_m", JsonNumber(f.k_N_m)},
                   {"trials", f.trials},
                   {"zeta_sd", JsonNumber(f.zeta_sd)},
                   {"mu_sd", JsonNumber(f.mu_sd)},
                   {"measurement_sd", Vector3(f.measurement_sd)}});
  return out;
}

}  // namespace

json DiscoveryJson(const DiscoveryResult& r) {
  json rounds = json::array(), findings = json::array(), residuals = json::array();
  for (const auto& round : r.rounds) rounds.push_back(RoundJson(round));
  for (const auto& f : r.findings)
    findings.push_back({{"key", f.key},
                        {"name", f.name},
                        {"parameter", f.parameter},
                        {"unit", f.unit},
                        {"status", ToString(f.status)},
                        {"form", ToString(f.form)},
                        {"surfaces", f.surfaces},
                        {"estimate", JsonNumber(f.estimate)},
                        {"se", JsonNumber(f.se)},
                        {"values", ValuesJson(f.values)},
                        {"partner", f.partner},
                        {"separating_measurement", f.separating_measurement},
                        {"gap_shrink", JsonNumber(f.gap_shrink)}});
  for (const auto& t : r.residuals)
    residuals.push_back({{"id", t.id},
                         {"surface", t.surface},
                         {"angle_deg", JsonNumber(t.angle_deg)},
                         {"speed_m_s", JsonNumber(t.speed_m_s)},
                         {"baseline", Vector3(t.baseline)},
                         {"final_model", Vector3(t.final_model)},
                         {"marker_ratio", JsonNumber(t.marker_ratio)}});
  return {{"success", r.success},
          {"message", r.message},
          {"trials_used", r.trials_used},
          {"trials_skipped", r.trials_skipped},
          {"baseline", SurfacesJson(r.baseline)},
          {"final_model", SurfacesJson(r.final_model)},
          {"measurement_sd", Vector3(r.measurement_sd)},
          {"effects", ValuesJson(r.effects)},
          {"held_out_error_unit", kHeldOutErrorUnit},
          {"held_out_density_unit", kHeldOutDensityUnit},
          {"rounds", rounds},
          {"findings", findings},
          {"unexplained", r.unexplained},
          {"remaining", TestsJson(r.remaining)},
          {"residuals", residuals},
          {"verdict", r.verdict},
          {"seconds", JsonNumber(r.seconds)},
          {"simulations", r.simulations}};
}

json PlanJson(const Plan& p) {
  json conditions = json::array();
  for (const auto& c : p.conditions)
    conditions.push_back({{"surface", c.surface},
                          {"angle_deg", JsonNumber(c.angle_deg)},
                          {"speed_low_m_s", JsonNumber(c.speed_low_m_s)},
                          {"speed_high_m_s", JsonNumber(c.speed_high_m_s)},
                          {"trials", c.trials},
                          {"information_per_trial", JsonNumber(c.information_per_trial)},
                          {"share", JsonNumber(c.share)}});
  return {{"key", p.key},
          {"size", JsonNumber(p.size)},
          {"unit", p.unit},
          {"trials", p.trials},
          {"level", JsonNumber(p.level)},
          {"detection_limit", JsonNumber(p.detection_limit)},
          {"power", JsonNumber(p.power)},
          {"trials_needed", JsonNumber(p.trials_needed)},
          {"bootstrap",
           {{"draws", p.bootstrap_draws},
            {"detected", p.bootstrap_detected},
            {"likelihood_ratio_significant", p.bootstrap_lr_significant},
            {"power", JsonNumber(p.bootstrap_power)},
            {"power_low", JsonNumber(p.bootstrap_low)},
            {"power_high", JsonNumber(p.bootstrap_high)}}},
          {"conditions", conditions}};
}

}  // namespace hoof::discovery
