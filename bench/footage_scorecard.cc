// The everyday-footage scorecard (docs/tracking.md, "Everyday footage: the scorecard"): renders
// clips of a ball bouncing in a room with the synth library's footage renderer, sets each up as
// `hoofimpact init` does with no options (SetUpTrial), measures it as `hoofimpact track` does
// (AnalyzeTrial), and matches the impacts measured to the bounces the renderer knows. It
// counts, per cell, the bounces found, e within --e-tol of the truth among those found, and
// impacts invented (measured where no bounce was, or any impact on a clip that holds none),
// and names the worst clips. It asserts nothing, and is neither a ctest test nor a Google
// Benchmark.
//   nice -n 10 build/bench/footage_scorecard --seeds 10 --jobs 2
//
// A cell is scene x timing x codec x camera; seed k of every cell renders with
// FootageSpec::seed = k. A bounce counts (is "measurable") when its contact is in view and the
// flights on both sides of it show the ball whole in at least --min-arc-frames distinct
// captures each, over each capture's whole exposure (WholeCaptures); e is compared with the
// renderer's e of that bounce (along the surface normal, in W). Clips are rendered into --dir and
// removed once scored (--keep keeps them). The result does not depend on --jobs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/parallel.h"
#include "io/atomic_file.h"
#include "pipeline/study_format.h"
#include "pipeline/trial_analysis.h"
#include "pipeline/trial_setup.h"
#include "synth/footage_renderer.h"

namespace fs = std::filesystem;
using namespace hoof;

namespace {

/// What the room holds.
enum class Scene { kPlain, kRoom, kTable, kThrown, kSpun };
const char* Name(Scene s) {
  switch (s) {
    case Scene::kPlain:
      return "plain";  // a plain wall and floor, no hand: the ball dropped
    case Scene::kRoom:
      return "room";  // shelves and clutter, a hand that lets go, a shadow
    case Scene::kTable:
      return "table";  // clutter, a hand, a table whose front edge is not where it bounces
    case Scene::kThrown:
      return "thrown";  // clutter, a hand that throws it sideways with spin: mu_eff
    case Scene::kSpun:
      return "spun";  // thrown so, a striped ball, a 2 ms exposure: its spin from its stripes
  }
  return "?";
}

/// How the frames are timed.
struct Timing {
  std::string name;
  synth::FootageTimingOptions options;
  double fps_stated = 0;  ///< --fps given to init (a slow-motion file's capture rate), or 0
};

std::vector<Timing> Timings() {
  std::vector<Timing> t;
  for (double fps : {25.0, 30.0, 60.0}) {
    synth::FootageTimingOptions o = synth::TimingOf(synth::TimingPreset::kPhone);
    o.capture_fps = fps;
    t.push_back({"phone" + std::to_string(static_cast<int>(fps)), o, 0});
  }
  t.push_back({"slowmo240in30", synth::TimingOf(synth::TimingPreset::kSlowMotion), 240});
  t.push_back({"screen30in60", synth::TimingOf(synth::TimingPreset::kScreenRecording), 0});
  return t;
}

/// The camera: level (a little tilt and roll, as a phone on a shelf), or tilted and rolled.
struct Camera {
  std::string name;
  double tilt_deg, roll_deg;
};

struct Cell {
  Scene scene;
  Timing timing;
  synth::FootageCodec codec;
  Camera camera;
  std::string Key() const {
    return std::string(Name(scene)) + "/" + timing.name + "/" + synth::ToString(codec) + "/" +
           camera.name;
  }
};

synth::FootageSpec SpecOf(const Cell& c, int seed, int width, int height) {
  synth::FootageSpec s = synth::DefaultFootageSpec(synth::FootageScenario::kBounce);
  s.seed = static_cast<std::uint64_t>(seed);
  s.camera.width_px = width;
  s.camera.height_px = height;
  s.camera.tilt_deg = c.camera.tilt_deg;
  s.camera.roll_deg = c.camera.roll_deg;
  s.codec = c.codec;
  s.timing = c.timing.options;
  s.timing.duration_s = 2.0;
  switch (c.scene) {
    case Scene::kPlain:
      s.room.clutter = false;
      s.hand.enabled = false;
      break;
    case Scene::kRoom:
      break;
    case Scene::kTable:
      s.room.surface = synth::ContactSurface::kTable;
      break;
    case Scene::kThrown:
      s.launch.v_W_m_s = Eigen::Vector3d(0.6, 0.4, 0.0);
      s.launch.w_W_rad_s = Eigen::Vector3d(0.0, 0.0, -15.0);
      s.launch.x_m = -0.25;
      s.ball.texture = synth::BallTexture::kCross;
      break;
    case Scene::kSpun:
      s.launch.v_W_m_s = Eigen::Vector3d(0.6, 0.4, 0.0);
      s.launch.w_W_rad_s = Eigen::Vector3d(0.0, 0.0, -15.0);
      s.launch.x_m = -0.25;
      s.ball.texture = synth::BallTexture::kStripes;
      s.timing.exposure_s = 0.002;
      break;
  }
  return s;
}

/// One truth bounce and what was measured of it.
struct BounceScore {
  bool measurable = false, found = false;
  /// Measurable by the ball at mid-exposure alone, but not by whole exposures (WholeCaptures).
  bool smeared = false;
  double e_truth = NAN, e = NAN, e_se = NAN, mu_truth = NAN, mu = NAN;
  /// The spin about the camera's axis in the trial's W sense (counterclockwise as shown),
  /// before and after; the truth is known where the ball is textured.
  bool textured = false;
  double w_truth[2] = {NAN, NAN}, w[2] = {NAN, NAN};
};

struct ClipScore {
  std::string error;  ///< init or track failed (no impact measured at all)
  std::vector<BounceScore> bounces;
  int invented = 0;
};

/// Distinct captures of the flight between t0 and t1 that show the ball whole, each a sample of
/// that flight alone: its exposure (centred on its time) lies between t0 and t1, so that it does
/// not smear the ball across the contact, and the ball stays whole in the frame over the whole
/// exposure (its image moved by its image velocity, from the neighbouring captures of the same
/// flight, over half the exposure each way). The truth is the ball at mid-exposure only.
/// With `mid_exposure`, every capture whose ball is whole at its mid-exposure time counts.
int WholeCaptures(const synth::FootageTruth& t, double t0, double t1, bool mid_exposure = false) {
  const double T = t.spec.sensor.motion_blur && !mid_exposure ? t.schedule.exposure_s : 0.0;
  // One row per capture, in time order.
  std::vector<const synth::FootageFrameTruth*> caps;
  for (const auto& f : t.frames)
    if (caps.empty() || f.frame.capture_index != caps.back()->frame.capture_index)
      caps.push_back(&f);
  std::set<int> captures;
  for (std::size_t i = 0; i < caps.size(); ++i) {
    const auto& f = *caps[i];
    if (!(f.frame.t_s - 0.5 * T > t0 && f.frame.t_s + 0.5 * T < t1) ||
        f.visibility != synth::BallVisibility::kVisible)
      continue;
    double smear = 0.0;  // px the image moves in half the exposure
    if (T > 0) {
      const auto* a = i > 0 && caps[i - 1]->arc == f.arc ? caps[i - 1] : &f;
      const auto* b = i + 1 < caps.size() && caps[i + 1]->arc == f.arc ? caps[i + 1] : &f;
      if (b->frame.t_s > a->frame.t_s)
        smear = 0.5 * T * (b->center_px - a->center_px).norm() / (b->frame.t_s - a->frame.t_s);
    }
    const double r = f.radius_px + smear;
    if (f.center_px.x() - r < 0 || f.center_px.y() - r < 0 || f.center_px.x() + r > t.width_px ||
        f.center_px.y() + r > t.height_px)
      continue;
    captures.insert(f.frame.capture_index);
  }
  return static_cast<int>(captures.size());
}

ClipScore ScoreClip(const Cell& c, int seed, const fs::path& dir, int width, int height,
                    int min_arc_frames, bool keep) {
  ClipScore out;
  const fs::path clip_dir = dir / (c.Key() + "/seed" + std::to_string(seed));
  std::string folder = clip_dir.string();
  const synth::FootageResult r =
      synth::RenderFootage(SpecOf(c, seed, width, height), clip_dir, /*overwrite=*/true);
  const synth::FootageTruth& truth = r.truth;
  // The bounces that count, and their truth.
  const auto& b = truth.bounces;
  for (std::size_t i = 0; i < b.size(); ++i) {
    BounceScore s;
    const double before = i == 0 ? truth.release_time_s : b[i - 1].world.t_s;
    const double after = i + 1 < b.size() ? b[i + 1].world.t_s : 1e300;
    const auto enough = [&](bool mid_exposure) {
      return b[i].in_view &&
             WholeCaptures(truth, before, b[i].world.t_s, mid_exposure) >= min_arc_frames &&
             WholeCaptures(truth, b[i].world.t_s, after, mid_exposure) >= min_arc_frames;
    };
    s.measurable = enough(false);
    s.smeared = !s.measurable && enough(true);
    s.e_truth = b[i].world.e;
    s.mu_truth = b[i].world.mu_eff;
    // A turn about the camera's +z (x toward y in the image) is clockwise as shown: the trial's
    // W, whose y points up the image, has the opposite sense.
    s.textured = c.scene == Scene::kThrown || c.scene == Scene::kSpun;
    s.w_truth[0] = -(truth.R_CW * b[i].world.w_before_rad_s).z();
    s.w_truth[1] = -(truth.R_CW * b[i].world.w_after_rad_s).z();
    out.bounces.push_back(s);
  }
  const fs::path trial = clip_dir / "trial";
  try {
    pipeline::TrialSetupOptions o;
    o.fps = c.timing.fps_stated;
    // A folder of PNG frames records no rate: the user states the one it plays at.
    if (o.fps == 0 && c.codec == synth::FootageCodec::kPng)
      o.fps = synth::ContainerFps(c.timing.options);
    const pipeline::TrialSetup setup = pipeline::SetUpTrial(r.clip, trial, o);
    io::CreateFolder(trial);
    for (const auto& [name, bytes] : pipeline::TrialFiles(setup))
      io::WriteTextAtomically(trial / name, bytes);
    const pipeline::TrialAnalysis a = pipeline::AnalyzeTrial(pipeline::ReadTrial(trial));
    if (a.impacts.empty() && !a.error.empty()) out.error = a.error;
    // Each measured impact to the truth bounce nearest in time, within a capture period.
    const double period = 1.0 / c.timing.options.capture_fps;
    for (const auto& k : a.impacts) {
      if (!k.success) continue;
      std::size_t best = b.size();
      double gap = 1.5 * std::max(period, 1.0 / synth::ContainerFps(c.timing.options));
      for (std::size_t i = 0; i < b.size(); ++i)
        if (std::abs(k.impact_time_s - b[i].world.t_s) < gap) {
          gap = std::abs(k.impact_time_s - b[i].world.t_s);
          best = i;
        }
      if (best == b.size() || out.bounces[best].found) {
        ++out.invented;
        continue;
      }
      out.bounces[best].found = true;
      out.bounces[best].e = k.e;
      out.bounces[best].e_se = k.e_se;
      out.bounces[best].mu = k.mu_eff;
      out.bounces[best].w[0] = k.w_before_rad_s;
      out.bounces[best].w[1] = k.w_after_rad_s;
    }
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  if (!keep) fs::remove_all(clip_dir);
  return out;
}

/// A clip without an impact: any impact measured is invented.
ClipScore ScoreEmpty(synth::FootageScenario scenario, int seed, const fs::path& dir, int width,
                     int height, bool keep) {
  ClipScore out;
  synth::FootageSpec s = synth::DefaultFootageSpec(scenario);
  s.seed = static_cast<std::uint64_t>(seed);
  s.camera.width_px = width;
  s.camera.height_px = height;
  const fs::path clip_dir =
      dir / (std::string("empty/") + synth::ToString(scenario) + "/seed" + std::to_string(seed));
  const synth::FootageResult r = synth::RenderFootage(s, clip_dir, /*overwrite=*/true);
  const fs::path trial = clip_dir / "trial";
  try {
    const pipeline::TrialSetup setup = pipeline::SetUpTrial(r.clip, trial, {});
    io::CreateFolder(trial);
    for (const auto& [name, bytes] : pipeline::TrialFiles(setup))
      io::WriteTextAtomically(trial / name, bytes);
    const pipeline::TrialAnalysis a = pipeline::AnalyzeTrial(pipeline::ReadTrial(trial));
    for (const auto& k : a.impacts)
      if (k.success) ++out.invented;
    out.error = a.error;
  } catch (const std::exception& e) {
    out.error = e.what();  // a refusal: what a clip without an impact should get
  }
  if (!keep) fs::remove_all(clip_dir);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Scorecard of init + track on rendered everyday footage"};
  int seeds = 10, jobs = 0, width = 640, height = 360, min_arc_frames = 3;
  double e_tol = 0.02, w_tol = 0.2;
  std::string dir = (fs::temp_directory_path() / "hoofimpact-footage-scorecard").string();
  std::string only;
  bool keep = false;
  app.add_option("--seeds", seeds, "Seeds per cell")->check(CLI::PositiveNumber);
  app.add_option("--jobs", jobs, "Threads (0: all cores)");
  app.add_option("--width-px", width, "Frame width")->check(CLI::Range(64, 4096));
  app.add_option("--height-px", height, "Frame height")->check(CLI::Range(64, 4096));
  app.add_option("--e-tol", e_tol, "e counts as right within this of the truth");
  app.add_option("--w-tol", w_tol, "A spin counts as right within this fraction of the truth");
  app.add_option("--min-arc-frames", min_arc_frames,
                 "A bounce counts when both its flights show the ball whole in this many captures");
  app.add_option("--dir", dir, "Where clips are rendered");
  app.add_option("--only", only, "Only the cells whose key contains this text");
  app.add_flag("--keep", keep, "Keep the rendered clips");
  CLI11_PARSE(app, argc, argv);

  std::vector<Cell> cells;
  for (Scene scene : {Scene::kPlain, Scene::kRoom, Scene::kTable, Scene::kThrown, Scene::kSpun})
    for (const Timing& timing : Timings())
      for (synth::FootageCodec codec : {synth::FootageCodec::kPng, synth::FootageCodec::kH264})
        for (const Camera& camera : {Camera{"level", 4.0, 1.5}, Camera{"tilted", 18.0, 9.0}}) {
          Cell c{scene, timing, codec, camera};
          if (only.empty() || c.Key().find(only) != std::string::npos) cells.push_back(c);
        }
  struct Job {
    std::size_t cell;
    int seed;
  };
  std::vector<Job> work;
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (int s = 1; s <= seeds; ++s) work.push_back({c, s});
  std::vector<ClipScore> scores(work.size());
  std::mutex print;
  std::size_t done = 0;
  core::ParallelFor(work.size(), jobs, [&](std::size_t i) {
    const Job& j = work[i];
    try {
      scores[i] = ScoreClip(cells[j.cell], j.seed, dir, width, height, min_arc_frames, keep);
    } catch (const std::exception& e) {
      scores[i].error = std::string("rendering: ") + e.what();
    }
    std::lock_guard<std::mutex> lock(print);
    std::fprintf(stderr, "\r%zu / %zu clips", ++done, work.size());
  });
  std::fprintf(stderr, "\n");

  // Per cell, and over all cells.
  struct Tally {
    int measurable = 0, found = 0, e_ok = 0, invented = 0, clips = 0, failed = 0;
    int mu_n = 0, mu_ok = 0, within_2se = 0;
    int spin_n = 0, spin_measured = 0, spin_ok = 0;
    int smeared = 0, smeared_found = 0;
    double worst = 0;
    std::string worst_clip;
  };
  std::map<std::string, Tally> by_cell;
  Tally all;
  for (std::size_t i = 0; i < work.size(); ++i) {
    const std::string key = cells[work[i].cell].Key();
    for (Tally* t : {&by_cell[key], &all}) {
      const ClipScore& s = scores[i];
      ++t->clips;
      if (!s.error.empty()) ++t->failed;
      t->invented += s.invented;
      for (const auto& b : s.bounces) {
        if (b.smeared) {
          ++t->smeared;
          t->smeared_found += b.found ? 1 : 0;
        }
        if (!b.measurable) continue;
        ++t->measurable;
        if (!b.found) continue;
        ++t->found;
        const double err = std::abs(b.e - b.e_truth);
        if (err < e_tol) ++t->e_ok;
        if (err < 2 * b.e_se) ++t->within_2se;
        if (std::isfinite(b.mu_truth) && b.mu_truth > 0 && std::isfinite(b.mu)) {
          ++t->mu_n;
          if (std::abs(b.mu - b.mu_truth) < 0.05) ++t->mu_ok;
        }
        for (int side = 0; side < 2 && b.textured; ++side) {
          ++t->spin_n;
          if (!std::isfinite(b.w[side])) continue;
          ++t->spin_measured;
          if (std::abs(b.w[side] - b.w_truth[side]) < w_tol * std::abs(b.w_truth[side]))
            ++t->spin_ok;
        }
        if (err > t->worst) {
          t->worst = err;
          t->worst_clip = key + " seed " + std::to_string(work[i].seed);
        }
      }
    }
  }
  const auto pct = [](int a, int b) { return b > 0 ? 100.0 * a / b : NAN; };
  std::printf(
      "| cell | clips | clips failed | bounces measurable | found | e within %.2f | e within "
      "2 s.e. | mu_eff within 0.05 | spin measured | spin within %.0f %% | invented | worst e "
      "error |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|---|\n",
      e_tol, 100 * w_tol);
  const auto row = [&](const std::string& name, const Tally& t) {
    std::printf(
        "| %s | %d | %d | %d | %d (%.1f %%) | %d (%.1f %%) | %.1f %% | %d / %d | %d / %d | %d | %d "
        "| %.4f (%s) |\n",
        name.c_str(), t.clips, t.failed, t.measurable, t.found, pct(t.found, t.measurable), t.e_ok,
        pct(t.e_ok, t.found), pct(t.within_2se, t.found), t.mu_ok, t.mu_n, t.spin_measured,
        t.spin_n, t.spin_ok, t.invented, t.worst, t.worst_clip.c_str());
  };
  for (const auto& [key, t] : by_cell) row(key, t);
  row("all", all);
  std::printf(
      "\nNot counted: %d bounces whose flights show the ball whole at mid-exposure in enough "
      "captures, but not over whole exposures (one smeared across the contact or the frame's "
      "edge); %d of them measured\n",
      all.smeared, all.smeared_found);

  // Clips that hold no impact.
  int empty_clips = 0, empty_invented = 0, empty_refused = 0;
  for (auto scenario : {synth::FootageScenario::kNeverLands, synth::FootageScenario::kStill,
                        synth::FootageScenario::kHandOnly})
    for (int s = 1; s <= seeds; ++s) {
      const ClipScore c = ScoreEmpty(scenario, s, dir, width, height, keep);
      ++empty_clips;
      empty_invented += c.invented;
      if (!c.error.empty()) ++empty_refused;
    }
  std::printf(
      "\nClips without an impact (never lands, still, hand only): %d clips, %d refused "
      "or reported without an impact, %d impacts invented\n",
      empty_clips, empty_refused, empty_invented);
  return 0;
}
