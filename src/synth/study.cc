#include "synth/study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>

#include "core/parallel.h"
#include "io/atomic_file.h"
#include "synth/projection.h"
#include "synth/trial_files.h"

namespace hoof::synth {
namespace fs = std::filesystem;

void StudyDesign::Validate() const {
  if (name.empty()) throw std::invalid_argument("study.name must not be empty");
  if (surfaces.empty()) throw std::invalid_argument("study.surfaces must not be empty");
  if (angles_deg.empty()) throw std::invalid_argument("study.angles_deg must not be empty");
  if (speeds_m_s.empty()) throw std::invalid_argument("study.speeds_m_s must not be empty");
  if (trials_per_cell < 1 || trials_per_cell > 1000)
    throw std::invalid_argument("study.trials_per_cell = " + std::to_string(trials_per_cell) +
                                ": must be in [1, 1000]");
  if (!(scatter_scale >= 0 && scatter_scale <= 4))
    throw std::invalid_argument("study.scatter_scale = " + std::to_string(scatter_scale) +
                                ": must be in [0, 4]");
  if (!(out_of_plane_random_deg >= 0 && out_of_plane_random_deg < 60))
    throw std::invalid_argument("study.out_of_plane_random_deg = " +
                                std::to_string(out_of_plane_random_deg) + ": must be in [0, 60)");
  for (const TrialSpec& t : Trials()) t.Validate();
}

std::vector<TrialSpec> StudyDesign::Trials() const {
  std::vector<StudyCell> design = cells;
  if (design.empty())
    for (dynamics::Surface s : surfaces)
      for (double angle : angles_deg)
        for (double speed : speeds_m_s) design.push_back({s, angle, speed});
  std::vector<TrialSpec> trials;
  std::uint64_t index = 0;
  for (const StudyCell& cell : design)
    for (int rep = 1; rep <= trials_per_cell; ++rep, ++index) {
      TrialSpec t;
      char id[96];
      std::snprintf(id, sizeof(id), "%s_%gdeg_v%.2f_r%d",
                    dynamics::SurfaceName(cell.surface).c_str(), cell.angle_deg, cell.speed_m_s,
                    rep);
      t.id = id;
      t.surface = cell.surface;
      t.angle_deg = cell.angle_deg;
      t.speed_m_s = cell.speed_m_s;
      t.seed = MixSeed(seed, index);
      t.scatter_parameters = scatter_parameters;
      t.scatter_scale = scatter_scale;
      t.hidden = hidden;
      if (out_of_plane_random_deg > 0) {
        std::mt19937_64 rng(MixSeed(t.seed, 99));
        std::uniform_real_distribution<double> u(-out_of_plane_random_deg, out_of_plane_random_deg);
        t.hidden.out_of_plane = {u(rng), u(rng), 100 * u(rng), 100 * u(rng)};
      }
      trials.push_back(t);
    }
  return trials;
}

namespace {

/// The trials that the study.json already in `study_dir` lists (none when there is none). A
/// study there is an error unless `overwrite`: its trials would fail one by one, and study.json
/// would be rewritten without them. Throws std::runtime_error naming the file.
std::vector<std::string> ListedTrials(const fs::path& study_dir, bool overwrite) {
  const fs::path file = study_dir / "study.json";
  if (!fs::exists(file)) return {};
  if (!overwrite)
    throw std::runtime_error(file.string() +
                             " exists: the folder holds a study already; render into another "
                             "folder, or add --overwrite to replace the trials of this design "
                             "(the study's other trials stay listed)");
  try {
    std::ifstream in(file);
    const nlohmann::json j = nlohmann::json::parse(in);
    return j.at("trials").get<std::vector<std::string>>();
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": cannot read the trials it lists (" + e.what() +
                             "); move it away to render a new study here");
  }
}

}  // namespace

StudyResult RenderStudy(const StudyDesign& design, const SpecimenGeometry& geometry,
                        const RenderOptions& options, const fs::path& study_dir, int threads,
                        bool overwrite,
                        const std::function<void(int, int, const std::string&)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  design.Validate();
  geometry.Validate();
  options.Validate();
  // Trials an earlier study in this folder lists: refused without overwrite (before anything is
  // rendered or written), kept in the list with it.
  const std::vector<std::string> listed = ListedTrials(study_dir, overwrite);
  std::error_code ec;
  fs::create_directories(study_dir, ec);
  if (ec || !fs::is_directory(study_dir))
    throw std::runtime_error("cannot create study folder '" + study_dir.string() + "'" +
                             (ec ? ": " + ec.message() : std::string()));
  StudyResult result;
  for (const TrialSpec& t : design.Trials()) result.trials.push_back({t, false, {}, {}});
  std::vector<dynamics::Surface> used;
  for (const StudyTrial& t : result.trials) used.push_back(t.spec.surface);
  const SceneAssets assets = BuildSceneAssets(geometry, options, used, design.seed);

  const int total = static_cast<int>(result.trials.size());
  threads = std::min(core::ResolveJobs(threads), std::max(total, 1));
  const int cv_threads = cv::getNumThreads();
  cv::setNumThreads(threads > 1 ? 1 : cv_threads);  // parallel across trials, not inside
  // OpenCV makes the operation object of cv::Mat::zeros, ones and eye lazily, unsynchronised (a
  // data race ThreadSanitizer finds between two threads). The project's own code makes its
  // matrices with cv::Mat(size, type, cv::Scalar) instead; this makes the object before the
  // threads, for OpenCV's own uses inside the calls the renderer makes.
  (void)cv::Mat(cv::Mat::zeros(1, 1, CV_32FC2));
  int done = 0;
  std::mutex mutex;
  core::ParallelFor(result.trials.size(), threads, [&](std::size_t i) {
    StudyTrial& st = result.trials[i];
    try {
      st.result = RenderTrial(st.spec, geometry, options, assets, study_dir / st.spec.id, overwrite,
                              /*in_study=*/true);
      st.ok = true;
    } catch (const std::exception& e) {
      st.error = e.what();
    }
    const std::lock_guard<std::mutex> lock(mutex);
    ++done;
    if (progress) progress(done, total, st.spec.id);
  });
  cv::setNumThreads(cv_threads);

  // The earlier study's trials whose folders are still there stay listed, then this design's.
  std::vector<std::string> ids;
  for (const std::string& id : listed)
    if (fs::is_directory(study_dir / id)) ids.push_back(id);
  for (const StudyTrial& t : result.trials) {
    if (!t.ok)
      ++result.failed;
    else if (std::find(ids.begin(), ids.end(), t.spec.id) == ids.end())
      ids.push_back(t.spec.id);
  }
  io::WriteTextAtomically(study_dir / "study.json",
                          StudyJson(design.name, geometry, ids).dump(2) + "\n");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

void DrawUnreplicatedCells(StudyDesign& design, int per_angle, double lo_m_s, double hi_m_s) {
  if (per_angle < 1)
    throw std::invalid_argument("DrawUnreplicatedCells: per_angle must be >= 1, got " +
                                std::to_string(per_angle));
  if (!(lo_m_s > 0 && lo_m_s < hi_m_s && hi_m_s <= 20))
    throw std::invalid_argument(
        "DrawUnreplicatedCells: the speed range must satisfy 0 < lo_m_s < "
        "hi_m_s <= 20 m/s, got [" +
        std::to_string(lo_m_s) + ", " + std::to_string(hi_m_s) + "]");
  // Ids carry the speed to 0.01 m/s: the range must hold per_angle distinct ones, or the
  // redraws below would never end.
  if (std::round(hi_m_s * 100) - std::round(lo_m_s * 100) + 1 < 2.0 * per_angle)
    throw std::invalid_argument("DrawUnreplicatedCells: [" + std::to_string(lo_m_s) + ", " +
                                std::to_string(hi_m_s) +
                                "] m/s holds too few speeds distinct to 0.01 m/s for " +
                                std::to_string(per_angle) + " trials per surface and angle");
  std::mt19937_64 rng(MixSeed(design.seed, 0x5eed5));
  std::uniform_real_distribution<double> speed(lo_m_s, hi_m_s);
  std::set<std::string> ids;
  design.cells.clear();
  for (auto surface : design.surfaces)
    for (double angle : design.angles_deg)
      for (int k = 0; k < per_angle; ++k) {
        for (;;) {
          const double v = speed(rng);
          char id[96];
          std::snprintf(id, sizeof id, "%s_%gdeg_v%.2f", dynamics::SurfaceName(surface).c_str(),
                        angle, v);
          if (ids.insert(id).second) {
            design.cells.push_back({surface, angle, v});
            break;
          }
        }
      }
  design.trials_per_cell = 1;
}

}  // namespace hoof::synth
