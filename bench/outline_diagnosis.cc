// Diagnosis of an unmarked (outline) trial against the renderer's truth: the impact measured
// from the truth's own poses, from the truth's poses with E moved to where the outline's area
// centroid puts it, and from the pipeline's poses; and the pipeline's pose errors per frame.
// The trial folder needs study.json beside it (silhouette_scorecard --keep writes one).
//   build/bench/outline_diagnosis TRIAL_DIR [OFFSET_M [per-frame]]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/frames.h"
#include "kinematics/impact_kinematics.h"
#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"

using namespace hoof;

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  const std::string dir = argv[1];
  const double offset = argc > 2 ? std::stod(argv[2]) : 0.0;
  const auto spec = pipeline::ReadTrial(dir);
  const auto truth = nlohmann::json::parse(std::ifstream(dir + "/truth.json"));
  const double e_t = truth.at("e").get<double>();
  const double mu_t = truth.at("mu_eff").is_number() ? truth.at("mu_eff").get<double>() : NAN;
  std::vector<kinematics::PoseSample> ts, tso;
  for (const auto& f : truth.at("frames")) {
    kinematics::PoseSample s;
    s.t_s = f.at("t_s").get<double>();
    s.valid = true;
    s.p_WE = {f.at("p_WE_m")[0].get<double>(), f.at("p_WE_m")[1].get<double>()};
    s.theta_W_rad = f.at("theta_W_rad").get<double>();
    ts.push_back(s);
    s.p_WE += offset * core::BodyRotation(s.theta_W_rad).x_B();
    tso.push_back(s);
  }
  const auto show = [&](const char* name, const kinematics::ImpactKinematics& k) {
    std::printf("%-28s e %.4f (%+.4f)  mu %.4f (%+.4f)  w %.2f -> %.2f  %s\n", name, k.e, k.e - e_t,
                k.mu_eff, k.mu_eff - mu_t, k.w_before_rad_s, k.w_after_rad_s,
                k.success ? "" : k.message.c_str());
  };
  std::printf("truth e %.4f mu %.4f  w %.2f -> %.2f\n", e_t, mu_t,
              truth.at("w_before_rad_s").get<double>(), truth.at("w_after_rad_s").get<double>());
  const double fps = spec.fps;
  show("truth poses", kinematics::MeasureImpact(ts, fps, spec.surface_angle_deg, spec.specimen));
  show("truth poses, E offset",
       kinematics::MeasureImpact(tso, fps, spec.surface_angle_deg, spec.specimen));
  const auto a = pipeline::AnalyzeTrial(spec);
  show("pipeline", a.impact);
  if (a.round_end)
    std::printf(
        "round end: measured %d, p_BE %.3f %.3f px (se %.3f %.3f), r %.3f px, %d of %d; %s\n",
        a.round_end->measured, a.round_end->p_BE_px.x(), a.round_end->p_BE_px.y(),
        a.round_end->p_BE_se_px.x(), a.round_end->p_BE_se_px.y(), a.round_end->radius_px,
        a.round_end->frames_used, a.round_end->frames_tried, a.round_end->message.c_str());
  if (!a.success) std::printf("error: %s\n", a.error.c_str());
  std::vector<kinematics::PoseSample> ps, pc;
  Eigen::Vector2d mean{0, 0};
  int n = 0;
  for (std::size_t f = 0; f < a.poses.size() && f < ts.size(); ++f) {
    kinematics::PoseSample s{ts[f].t_s, a.poses[f].valid, a.poses[f].p_WE, a.poses[f].theta_W_rad};
    ps.push_back(s);
    s.p_WE -= offset * core::BodyRotation(s.theta_W_rad).x_B();
    pc.push_back(s);
    if (s.valid) mean += s.p_WE - ts[f].p_WE, ++n;
  }
  mean /= n;
  show("pipeline, E corrected",
       kinematics::MeasureImpact(pc, fps, spec.surface_angle_deg, spec.specimen));
  // Pipeline theta with truth positions, and vice versa.
  std::vector<kinematics::PoseSample> mix1 = ts, mix2 = pc;
  for (std::size_t f = 0; f < pc.size(); ++f) {
    mix1[f].theta_W_rad = pc[f].theta_W_rad;
    mix1[f].valid = pc[f].valid;
    mix2[f].theta_W_rad = ts[f].theta_W_rad;
  }
  show("truth p, pipeline theta",
       kinematics::MeasureImpact(mix1, fps, spec.surface_angle_deg, spec.specimen));
  show("pipeline p(corr), truth th",
       kinematics::MeasureImpact(mix2, fps, spec.surface_angle_deg, spec.specimen));
  if (argc > 3)
    for (std::size_t f = 0; f < pc.size(); ++f) {
      const Eigen::Vector2d d = pc[f].p_WE - ts[f].p_WE - mean;
      std::printf("%3zu %d %s dp_um %+8.2f %+8.2f dth_mrad %+7.3f th %.4f\n", f,
                  pc[f].valid ? 1 : 0, truth.at("frames")[f].at("phase").get<std::string>().c_str(),
                  d.x() * 1e6, d.y() * 1e6, (pc[f].theta_W_rad - ts[f].theta_W_rad) * 1e3,
                  ts[f].theta_W_rad);
    }
  return 0;
}
