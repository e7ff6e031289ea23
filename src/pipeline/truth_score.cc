#include "pipeline/truth_score.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/frames.h"
#include "core/parallel.h"
#include "pipeline/study_format.h"

namespace hoof::pipeline {
namespace {

/// `v` as [x, y]; std::runtime_error naming the file and `field` otherwise.
Eigen::Vector2d Pair(const nlohmann::json& v, const std::string& field, const std::string& file) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    throw std::runtime_error(file + ": field \"" + field + "\" must be [x, y], found " + v.dump());
  return {v[0].get<double>(), v[1].get<double>()};
}

Eigen::Vector2d Vec(const nlohmann::json& j, const std::string& key, const std::string& file) {
  if (!j.contains(key)) throw std::runtime_error(file + ": field \"" + key + "\" is missing");
  return Pair(j.at(key), key, file);
}

/// An optional number of a frame (0 when absent).
double FrameNumber(const nlohmann::json& f, const std::string& key, const std::string& field,
                   const std::string& file) {
  if (!f.contains(key)) return 0.0;
  if (!f.at(key).is_number())
    throw std::runtime_error(file + ": field \"" + field + "\" must be a number, found " +
                             f.at(key).dump());
  return f.at(key).get<double>();
}

double Num(const nlohmann::json& j, const std::string& key, const std::string& file) {
  if (!j.contains(key) || !j.at(key).is_number())
    throw std::runtime_error(file + ": field \"" + key + "\" is missing or not a number");
  return j.at(key).get<double>();
}

/// truth.json's `impacts`: each one's touch time, e and mu_eff (null on a level surface).
std::vector<ImpactTruth> ReadImpacts(const nlohmann::json& impacts, const std::string& file) {
  if (!impacts.is_array()) throw std::runtime_error(file + ": field \"impacts\" is not an array");
  std::vector<ImpactTruth> out;
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    const nlohmann::json& k = impacts[i];
    const std::string at = "impacts[" + std::to_string(i) + "]";
    if (!k.is_object()) throw std::runtime_error(file + ": field \"" + at + "\" is not an object");
    ImpactTruth it;
    for (auto [key, value] :
         {std::pair<const char*, double*>{"touch_time_s", &it.touch_time_s}, {"e", &it.e}}) {
      if (!k.contains(key) || !k.at(key).is_number())
        throw std::runtime_error(file + ": field \"" + at + "." + key +
                                 "\" is missing or not a number");
      *value = k.at(key).get<double>();
    }
    it.mu_eff = k.contains("mu_eff") && k.at("mu_eff").is_number() ? k.at("mu_eff").get<double>()
                                                                   : core::kNaN;
    out.push_back(it);
  }
  return out;
}

/// The centre path of `a` against truth's center_px: its rms, largest error and count into `s`.
void ScoreCentre(const TrialAnalysis& a, const TrialTruth& t, TrialScore& s) {
  const tracking::ImageToWorld cam = TrialCamera(a.spec, a.m_per_px_used);
  double ss = 0;
  for (std::size_t f = 0; f < a.poses.size() && f < t.centre_px.size(); ++f) {
    const auto& pose = a.poses[f];
    if (!pose.valid || !t.centre_px[f]) continue;
    const Eigen::Vector2d p_WC =
        pose.p_WE + a.spec.specimen.d_EC_m * core::BodyRotation(pose.theta_W_rad).x_B();
    const double err = (cam.ToImage(p_WC) - *t.centre_px[f]).norm();
    if (!std::isfinite(err)) continue;
    ss += err * err;
    s.centre_max_px = std::max(s.centre_max_px, err);
    ++s.centre_count;
  }
  s.centre_rms_px = s.centre_count ? std::sqrt(ss / s.centre_count) : 0.0;
}

/// The clip's impacts against truth's: each true impact matched to the nearest measured one
/// within two frame periods.
void ScoreImpacts(const TrialAnalysis& a, const TrialTruth& t, TrialScore& s) {
  s.impacts_true = static_cast<int>(t.impacts.size());
  for (const auto& k : a.impacts) s.impacts_found += k.success ? 1 : 0;
  s.impacts_e_max_abs = t.impacts.empty() ? core::kNaN : 0.0;
  const double tolerance_s = 2.0 / a.spec.fps;
  bool any = false;
  for (const ImpactTruth& truth : t.impacts) {
    const kinematics::ImpactKinematics* best = nullptr;
    for (const auto& k : a.impacts)
      if (k.success && std::abs(k.impact_time_s - truth.touch_time_s) <= tolerance_s &&
          (!best || std::abs(k.impact_time_s - truth.touch_time_s) <
                        std::abs(best->impact_time_s - truth.touch_time_s)))
        best = &k;
    if (!best) continue;
    ++s.impacts_matched;
    any = true;
    s.impacts_e_max_abs = std::max(s.impacts_e_max_abs, std::abs(best->e - truth.e));
  }
  if (!any) s.impacts_e_max_abs = core::kNaN;
}

}  // namespace

TrialTruth ReadTruth(const std::filesystem::path& trial_dir) {
  const std::string file = (trial_dir / "truth.json").string();
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot open");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error(file + ": must hold a JSON object ({...})");
  TrialTruth t;
  t.impact_time_s = Num(j, "impact_time_s", file);
  t.v_SC_before = Vec(j, "v_SC_before_m_s", file);
  t.v_SC_after = Vec(j, "v_SC_after_m_s", file);
  t.w_before_rad_s = Num(j, "w_before_rad_s", file);
  t.w_after_rad_s = Num(j, "w_after_rad_s", file);
  t.e = Num(j, "e", file);
  t.mu_eff = j.contains("mu_eff") && j.at("mu_eff").is_number() ? j.at("mu_eff").get<double>()
                                                                : core::kNaN;
  if (j.contains("body")) {
    const nlohmann::json& b = j.at("body");
    if (!b.is_object() || !b.contains("kind") || !b.at("kind").is_string())
      throw std::runtime_error(file + ": field \"body.kind\" is missing or not a string");
    t.body = b.at("kind").get<std::string>();
  }
  // Only a body with markers has them drawn.
  const bool markers = t.body == "markers";
  if (!j.contains("frames") || !j.at("frames").is_array())
    throw std::runtime_error(file + ": field \"frames\" is missing");
  const nlohmann::json& frames = j.at("frames");
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const nlohmann::json& f = frames[i];
    const std::string at = "frames[" + std::to_string(i) + "]";
    if (!f.is_object() ||
        (markers && (!f.contains("markers_px") || !f.at("markers_px").is_object())))
      throw std::runtime_error(file + ": field \"" + at +
                               ".markers_px\" is missing or not an object");
    std::map<std::string, Eigen::Vector2d> m;
    if (markers)
      for (auto it = f.at("markers_px").begin(); it != f.at("markers_px").end(); ++it)
        m[it.key()] = Pair(it.value(), at + ".markers_px." + it.key(), file);
    t.markers_px.push_back(m);
    t.centre_px.push_back(f.contains("center_px")
                              ? std::optional(Pair(f.at("center_px"), at + ".center_px", file))
                              : std::nullopt);
    const double tilt =
        FrameNumber(f, "out_of_plane_tilt_rad", at + ".out_of_plane_tilt_rad", file);
    const double roll =
        FrameNumber(f, "out_of_plane_roll_rad", at + ".out_of_plane_roll_rad", file);
    if (tilt != 0.0 || roll != 0.0) t.out_of_plane = true;
  }
  if (j.contains("impacts")) t.impacts = ReadImpacts(j.at("impacts"), file);
  return t;
}

TrialScore ScoreTrial(const TrialAnalysis& a, const TrialTruth& t) {
  TrialScore s;
  double ss = 0;
  for (std::size_t f = 0; f < a.tracks.frames.size() && f < t.markers_px.size(); ++f)
    for (std::size_t m = 0; m < a.tracks.names.size(); ++m) {
      const auto& o = a.tracks.frames[f][m];
      const auto it = t.markers_px[f].find(a.tracks.names[m]);
      if (!o.found || it == t.markers_px[f].end()) continue;
      const double err = (o.p_I - it->second).norm();
      ss += err * err;
      s.marker_max_px = std::max(s.marker_max_px, err);
      ++s.marker_count;
    }
  s.marker_rms_px = s.marker_count ? std::sqrt(ss / s.marker_count) : 0.0;
  const auto& k = a.impact;
  s.v_before_rel = (k.v_SC_before - t.v_SC_before).norm() / t.v_SC_before.norm();
  s.v_after_rel = (k.v_SC_after - t.v_SC_after).norm() / t.v_SC_after.norm();
  s.w_before_abs = std::abs(k.w_before_rad_s - t.w_before_rad_s);
  s.w_after_abs = std::abs(k.w_after_rad_s - t.w_after_rad_s);
  s.e_abs = std::abs(k.e - t.e);
  s.mu_eff_abs = std::abs(k.mu_eff - t.mu_eff);
  s.impact_time_abs_s = std::abs(k.impact_time_s - t.impact_time_s);
  ScoreCentre(a, t, s);
  ScoreImpacts(a, t, s);
  return s;
}

StudyScoreSummary SummarizeScores(const std::vector<StudyTrialScore>& trials) {
  StudyScoreSummary out;
  out.trials = static_cast<int>(trials.size());
  double ss = 0.0, ss_centre = 0.0;
  long count = 0, count_centre = 0;
  // The largest of the numbers among `values` (a ball's w errors are NaN); w's stays NaN when no
  // trial has one.
  out.w_max_abs_rad_s = core::kNaN;
  const auto worst = [](double& into, std::initializer_list<double> values) {
    for (double v : values)
      if (std::isfinite(v)) into = std::isnan(into) ? v : std::max(into, v);
  };
  for (const auto& t : trials) {
    if (!t.scored()) continue;
    ++out.scored;
    const TrialScore& s = t.score;
    ss += s.marker_rms_px * s.marker_rms_px * s.marker_count;
    count += s.marker_count;
    ss_centre += s.centre_rms_px * s.centre_rms_px * s.centre_count;
    count_centre += s.centre_count;
    out.marker_max_px = std::max(out.marker_max_px, s.marker_max_px);
    out.centre_max_px = std::max(out.centre_max_px, s.centre_max_px);
    worst(out.v_SC_max_rel, {s.v_before_rel, s.v_after_rel});
    worst(out.w_max_abs_rad_s, {s.w_before_abs, s.w_after_abs});
    worst(out.e_max_abs, {s.e_abs});
    worst(out.mu_eff_max_abs, {s.mu_eff_abs});
    out.impacts_true += s.impacts_true;
    out.impacts_matched += s.impacts_matched;
  }
  out.marker_rms_px = count > 0 ? std::sqrt(ss / static_cast<double>(count)) : 0.0;
  out.centre_rms_px =
      count_centre > 0 ? std::sqrt(ss_centre / static_cast<double>(count_centre)) : 0.0;
  return out;
}

StudyScore ScoreStudy(const std::filesystem::path& study_dir, const TrialAnalysisOptions& options,
                      int jobs) {
  const StudySpec study = ReadStudy(study_dir);
  StudyScore out;
  out.trials.resize(study.trial_dirs.size());
  core::ParallelFor(out.trials.size(), jobs, [&](std::size_t i) {
    StudyTrialScore& t = out.trials[i];
    t.dir = study.trial_dirs[i];
    try {
      const TrialSpec spec = ReadTrial(t.dir, study);
      t.id = spec.id;
      const TrialAnalysis analysis = AnalyzeTrial(spec, options);
      t.flags = analysis.flags;
      if (!analysis.success) {
        t.error = analysis.error.empty() ? "the analysis failed" : analysis.error;
        return;
      }
      const TrialTruth truth = ReadTruth(t.dir);
      t.score = ScoreTrial(analysis, truth);
      t.truth_out_of_plane = truth.out_of_plane;
    } catch (const std::exception& e) {
      t.error = e.what();
    }
  });
  out.summary = SummarizeScores(out.trials);
  return out;
}

}  // namespace hoof::pipeline
