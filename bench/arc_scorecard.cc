// The joint-arc scorecard (docs/tracking.md, "Joint arcs"): closed-form bouncing balls
// (tests/support/bouncing_ball.h) sampled at 25, 30 and 60 fps at random contact phases, with
// Gaussian position noise, measured by kinematics::MeasureArcImpacts; per condition the rate of
// bounces found and measured, of |e - truth| < --e-tol, the coverage of e's 95 % interval, the
// rms of (e - truth) / s.e., impacts found where there is none, and the fitted direction of
// gravity. Also the capture rate from gravity of 240 fps clips whose times say 30 fps. It
// asserts nothing, and is neither a ctest test nor a Google Benchmark.
//   build/bench/arc_scorecard --seeds 200
//
// Seed k of a condition draws its clip from std::mt19937_64(k): drop height 0.3-1.2 m, sideways
// speed -0.5..0.5 m/s, e of each bounce 0.5-0.9, friction 0-0.3, the phase of frame 0 within a
// frame period. A bounce counts when both of its flights hold 3 or more frames with a position.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/parallel.h"
#include "kinematics/arc_impacts.h"
#include "kinematics/capture_rate.h"
#include "support/bouncing_ball.h"

using namespace hoof;

namespace {

bool g_verbose = false;
int g_trace = -1;

struct Condition {
  double fps;
  double noise_px;
  std::string kind;  ///< plain, rolled, gaps, blur, hand, contact, incline
  std::string Name() const {
    char s[64];
    std::snprintf(s, sizeof s, "%gfps/%gpx/%s", fps, noise_px, kind.c_str());
    return s;
  }
};

struct Tally {
  int bounces = 0, found = 0, measured = 0, e_ok = 0, covered = 0, false_impacts = 0, clips = 0;
  double z2 = 0, roll_z2 = 0, roll_err2 = 0;
  int roll_n = 0;
};

testing::BallClipOptions Draw(const Condition& c, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  testing::BallClipOptions o;
  o.fps = c.fps;
  o.frames = static_cast<int>(2.5 * c.fps);
  o.noise_px = c.noise_px;
  o.seed = seed;
  o.phase_s = U(rng) / c.fps;
  o.p0_G = {0, 0.3 + 0.9 * U(rng), 0};
  o.v0_G = {-0.5 + U(rng), 0, 0};
  o.e.clear();
  o.mu.clear();
  for (int k = 0; k < 8; ++k) {
    o.e.push_back(0.5 + 0.4 * U(rng));
    o.mu.push_back(0.3 * U(rng));
  }
  if (c.kind == "rolled") o.roll_deg = -20 + 40 * U(rng);
  if (c.kind == "gaps") {
    for (int f = 1; f < o.frames; ++f) {
      const double x = U(rng);
      if (x < 0.05)
        o.missing.push_back(f);
      else if (x < 0.10)
        o.repeated.push_back(f);
    }
  }
  if (c.kind == "blur") o.exposure_s = 1 / c.fps;
  if (c.kind == "hand") {
    // A hand carries the ball down at 1-2.5 m/s (no gravity: it is held) and lets go 2 to 6
    // frame periods before the touch; the clip starts 0.2-0.3 s before that.
    const double v_hand = 1 + 1.5 * U(rng), tau = (2 + 4 * U(rng)) / c.fps;
    o.release_s = 0.2 + 0.1 * U(rng);
    o.p0_G.y() = o.radius_m + v_hand * tau + 0.5 * 9.81 * tau * tau;
    o.v0_G.y() = -v_hand;
  }
  if (c.kind == "contact") o.contact_s = 0.005;
  if (c.kind == "incline") o.surface_angle_deg = 15;
  return o;
}

/// Every frame's role, the arcs and the impacts of one clip (--trace).
void Trace(const testing::BallClip& clip, const kinematics::ArcImpacts& r) {
  for (std::size_t f = 0; f < r.arcs.frames.size(); ++f)
    std::fprintf(stderr, "  frame %zu t %.4f arc %d %s chi2 %.2f\n", f, clip.poses[f].t_s,
                 r.arcs.frames[f].arc, kinematics::ArcFrameRoleName(r.arcs.frames[f].role),
                 r.arcs.frames[f].residual_chi2);
  for (const auto& b : clip.bounces)
    std::fprintf(stderr, "  truth touch %.4f e %.4f v_n %.3f\n", b.t_touch, b.e, b.v_before_S.y());
  for (const auto& k : r.impacts)
    std::fprintf(stderr, "  impact %d %s t %.4f e %.4f +- %.4f\n", k.index,
                 k.success ? "measured" : k.message.c_str(), k.impact_time_s, k.e, k.e_se);
}

/// Frames with a position strictly between t0 and t1.
int FramesBetween(const testing::BallClip& clip, double t0, double t1) {
  int n = 0;
  for (const auto& p : clip.poses) n += p.valid && p.t_s > t0 && p.t_s < t1;
  return n;
}

void Score(const Condition& c, std::uint64_t seed, double e_tol, Tally& t) {
  const testing::BallClipOptions o = Draw(c, seed);
  const testing::BallClip clip = testing::MakeBallClip(o);
  core::SpecimenParameters ball;
  ball.d_EC_m = 0;
  ball.end_radius_m = o.radius_m;
  const auto r = kinematics::MeasureArcImpacts(clip.poses, o.surface_angle_deg, ball);
  ++t.clips;
  if (g_verbose && g_trace == static_cast<int>(seed)) Trace(clip, r);
  std::vector<bool> matched(r.impacts.size(), false);
  for (std::size_t b = 0; b < clip.bounces.size(); ++b) {
    const auto& tb = clip.bounces[b];
    const double before_from = b == 0 ? o.release_s : clip.bounces[b - 1].t_sep;
    const double after_to = b + 1 < clip.bounces.size() ? clip.bounces[b + 1].t_touch : 1e9;
    if (FramesBetween(clip, before_from, tb.t_touch) < 3 ||
        FramesBetween(clip, tb.t_sep, after_to) < 3)
      continue;
    ++t.bounces;
    for (std::size_t i = 0; i < r.impacts.size(); ++i) {
      const auto& k = r.impacts[i];
      if (matched[i] || std::abs(k.impact_time_s - tb.t_touch) > 1.5 / o.fps) continue;
      matched[i] = true;
      ++t.found;
      if (!k.success) break;
      ++t.measured;
      const double de = k.e - tb.e;
      t.e_ok += std::abs(de) < e_tol;
      t.covered += tb.e >= k.e_ci_low && tb.e <= k.e_ci_high;
      t.z2 += de * de / (k.e_se * k.e_se);
      if (g_verbose && std::abs(de) > 3 * k.e_se)
        std::fprintf(stderr,
                     "%s seed %llu bounce %zu: e %.4f +- %.4f vs %.4f (z %.1f), samples %d/%d, "
                     "contact %zu, outliers %zu, t* %.4f vs %.4f\n",
                     c.Name().c_str(), static_cast<unsigned long long>(seed), b, k.e, k.e_se, tb.e,
                     de / k.e_se, k.limits.samples_before, k.limits.samples_after,
                     k.limits.contact_frames.size(), k.limits.outlier_frames.size(),
                     k.impact_time_s, tb.t_touch);
      break;
    }
  }
  // An impact matching no bounce at all (not only no counted one) is invented.
  for (std::size_t i = 0; i < r.impacts.size(); ++i) {
    bool any = false;
    for (const auto& tb : clip.bounces)
      any |= std::abs(r.impacts[i].impact_time_s - tb.t_touch) <= 1.5 / o.fps;
    t.false_impacts += !any;
  }
  if (r.arcs.status == kinematics::ArcFitStatus::kFitted) {
    const double err = r.arcs.roll_deg - o.roll_deg;
    t.roll_err2 += err * err;
    t.roll_z2 += err * err / (r.arcs.roll_se_deg * r.arcs.roll_se_deg);
    ++t.roll_n;
  }
}

/// A 240 fps capture stored at 30 fps: times i / 30, the scale known.
void SlowMotion(int seeds) {
  int measured = 0, covered = 0, nearest8 = 0;
  double sum = 0, z2 = 0;
  for (int s = 1; s <= seeds; ++s) {
    Condition c{240, 1.0, "plain"};
    testing::BallClipOptions o = Draw(c, static_cast<std::uint64_t>(s));
    o.frames = 480;
    testing::BallClip clip = testing::MakeBallClip(o);
    for (std::size_t i = 0; i < clip.poses.size(); ++i)
      clip.poses[i].t_s = static_cast<double>(i) / 30;
    const auto arcs = kinematics::FitFlightArcs(clip.poses, 0.0, 0.0);
    if (arcs.status != kinematics::ArcFitStatus::kFitted) continue;
    const auto rate = kinematics::CaptureRateFromGravity(arcs.a_norm, arcs.a_norm_se, 30, 0.0);
    if (!rate.measured) continue;
    ++measured;
    sum += rate.capture_fps;
    const double z = (rate.capture_fps - 240) / rate.capture_fps_se;
    z2 += z * z;
    covered += std::abs(z) < 1.96;
    nearest8 += rate.nearest_ratio == 8;
  }
  std::printf(
      "\n240 fps stored at 30 fps (1 px noise, %d clips): measured %d, mean capture rate "
      "%.3f /s, nearest whole ratio 8 in %d, |z| < 1.96 in %d, rms z %.2f\n",
      seeds, measured, measured ? sum / measured : NAN, nearest8, covered,
      measured ? std::sqrt(z2 / measured) : NAN);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Joint-arc scorecard: e of every bounce of closed-form bouncing balls"};
  std::vector<double> rates = {25, 30, 60}, noises = {0.3, 1.0};
  std::vector<std::string> kinds = {"plain", "rolled",  "gaps",   "blur",
                                    "hand",  "contact", "incline"};
  int seeds = 200, first_seed = 1, jobs = 0;
  double e_tol = 0.02;
  app.add_option("--fps", rates, "Frame rates")->delimiter(',')->capture_default_str();
  app.add_option("--noise-px", noises, "Position noise s.d. (px)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--kinds", kinds, "plain, rolled, gaps, blur, hand, contact, incline")
      ->delimiter(',')
      ->check(CLI::IsMember({"plain", "rolled", "gaps", "blur", "hand", "contact", "incline"}))
      ->capture_default_str();
  app.add_option("--seeds", seeds, "Clips per condition")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--first-seed", first_seed, "Seed of the first clip")->capture_default_str();
  app.add_option("--e-tol", e_tol, "Tolerance on e")->capture_default_str();
  app.add_option("--jobs", jobs, "Threads (0 = all cores)")->capture_default_str();
  app.add_option("--trace", g_trace, "With --verbose: every frame of this seed's clips (stderr)");
  app.add_flag("--verbose", g_verbose, "Name every e off its truth by more than 3 s.e. (stderr)");
  CLI11_PARSE(app, argc, argv);

  std::vector<Condition> conditions;
  for (const auto& k : kinds)
    for (double f : rates)
      for (double n : noises) conditions.push_back({f, n, k});
  std::vector<Tally> tallies(conditions.size());
  core::ParallelFor(conditions.size(), jobs, [&](std::size_t i) {
    for (int s = first_seed; s < first_seed + seeds; ++s)
      Score(conditions[i], static_cast<std::uint64_t>(s), e_tol, tallies[i]);
  });
  std::printf("%-24s %7s %7s %8s %8s %9s %7s %7s %9s %8s\n", "condition", "bounces", "found",
              "measured", "|de|<tol", "95% cover", "rms z", "false", "roll rms", "roll z");
  Tally all;
  for (std::size_t i = 0; i < conditions.size(); ++i) {
    const Tally& t = tallies[i];
    const auto pct = [](int a, int b) { return b ? 100.0 * a / b : NAN; };
    std::printf("%-24s %7d %6.1f%% %7.1f%% %7.1f%% %8.1f%% %7.2f %7d %8.3f° %8.2f\n",
                conditions[i].Name().c_str(), t.bounces, pct(t.found, t.bounces),
                pct(t.measured, t.found), pct(t.e_ok, t.measured), pct(t.covered, t.measured),
                t.measured ? std::sqrt(t.z2 / t.measured) : NAN, t.false_impacts,
                t.roll_n ? std::sqrt(t.roll_err2 / t.roll_n) : NAN,
                t.roll_n ? std::sqrt(t.roll_z2 / t.roll_n) : NAN);
    all.bounces += t.bounces;
    all.found += t.found;
    all.measured += t.measured;
    all.e_ok += t.e_ok;
    all.covered += t.covered;
    all.false_impacts += t.false_impacts;
    all.z2 += t.z2;
  }
  std::printf("%-24s %7d %6.1f%% %7.1f%% %7.1f%% %8.1f%% %7.2f %7d\n", "all", all.bounces,
              100.0 * all.found / all.bounces, 100.0 * all.measured / all.found,
              100.0 * all.e_ok / all.measured, 100.0 * all.covered / all.measured,
              std::sqrt(all.z2 / all.measured), all.false_impacts);
  SlowMotion(seeds);
  return 0;
}
