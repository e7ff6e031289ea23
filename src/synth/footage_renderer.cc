#include "synth/footage_renderer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "core/parallel.h"
#include "io/atomic_file.h"
#include "synth/footage_draw.h"
#include "synth/temporary_folder.h"

namespace hoof::synth {
namespace fs = std::filesystem;
namespace {

/// Writes delivered frames, in order, as PNGs or into one H.264 MP4.
class ClipWriter {
 public:
  ClipWriter(const fs::path& folder, const FootageTruth& truth)
      : folder_(folder),
        codec_(truth.spec.codec),
        tag_(truth.spec.camera.rotation_tag_deg),
        png_level_(truth.spec.png_compression) {
    if (codec_ != FootageCodec::kH264) return;
    file_ = folder / FootageClipName(codec_);
    const cv::Size stored(truth.stored_width_px, truth.stored_height_px);
    video_.open(file_.string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('a', 'v', 'c', '1'),
                truth.schedule.container_fps, stored, true);
    if (!video_.isOpened())
      throw std::runtime_error("cannot write '" + file_.string() +
                               "': OpenCV's FFmpeg writer does not open H.264 ('avc1') at " +
                               std::to_string(stored.width) + " x " +
                               std::to_string(stored.height));
  }
  void Write(int index, const cv::Mat& upright) {
    if (codec_ == FootageCodec::kH264) {
      video_.write(StoredFrame(upright, tag_));
      return;
    }
    char name[32];
    std::snprintf(name, sizeof name, "%06d.png", index);
    const fs::path path = folder_ / "frames" / name;
    if (!cv::imwrite(path.string(), upright, {cv::IMWRITE_PNG_COMPRESSION, png_level_}))
      throw std::runtime_error("cannot write frame '" + path.string() + "'");
  }
  void Finish() {
    if (codec_ != FootageCodec::kH264) return;
    video_.release();
    std::error_code ec;
    if (fs::file_size(file_, ec) == 0 || ec)
      throw std::runtime_error("cannot write '" + file_.string() +
                               "': the H.264 writer wrote nothing");
  }

 private:
  fs::path folder_, file_;
  FootageCodec codec_;
  int tag_ = 0, png_level_ = 1;
  cv::VideoWriter video_;
};

/// Draws the delivered frames in chunks (distinct captures in parallel) and hands each to
/// `write` in order; a repeat reuses the image of the capture it repeats.
void DrawFrames(const FootagePlan& plan, int first, int count, int jobs,
                const std::function<void(int, const cv::Mat&)>& write) {
  const FootageFrameRenderer renderer(plan, jobs);
  const auto& frames = plan.schedule.frames;
  const int end = std::min<int>(static_cast<int>(frames.size()), first + count);
  const int chunk = std::max(1, 4 * core::ResolveJobs(jobs));
  std::map<int, cv::Mat> done;
  for (int start = first; start < end; start += chunk) {
    std::vector<int> todo;
    for (int j = start; j < std::min(end, start + chunk); ++j) {
      const int k = frames[static_cast<std::size_t>(j)].capture_index;
      if (!done.count(k) && std::find(todo.begin(), todo.end(), k) == todo.end()) todo.push_back(k);
    }
    std::vector<cv::Mat> images(todo.size());
    core::ParallelFor(todo.size(), jobs,
                      [&](std::size_t i) { images[i] = renderer.Render(todo[i]); });
    for (std::size_t i = 0; i < todo.size(); ++i) done[todo[i]] = images[i];
    for (int j = start; j < std::min(end, start + chunk); ++j)
      write(j, done.at(frames[static_cast<std::size_t>(j)].capture_index));
    // Only the last capture can be shown again by a later frame.
    const int keep =
        frames[static_cast<std::size_t>(std::min(end, start + chunk) - 1)].capture_index;
    for (auto it = done.begin(); it != done.end();)
      it = it->first == keep ? std::next(it) : done.erase(it);
  }
}

}  // namespace

std::string FootageClipName(FootageCodec codec) {
  return codec == FootageCodec::kH264 ? "clip.mp4" : "frames/%06d.png";
}

cv::Mat StoredFrame(const cv::Mat& upright, int tag) {
  cv::Mat out;
  switch (tag) {
    case 90:
      cv::rotate(upright, out, cv::ROTATE_90_COUNTERCLOCKWISE);
      return out;
    case 180:
      cv::rotate(upright, out, cv::ROTATE_180);
      return out;
    case 270:
      cv::rotate(upright, out, cv::ROTATE_90_CLOCKWISE);
      return out;
    default:
      return upright;
  }
}

std::vector<cv::Mat> RenderFootageFrames(const FootagePlan& plan, int first, int count) {
  if (count < 0) count = static_cast<int>(plan.schedule.frames.size()) - first;
  std::vector<cv::Mat> out;
  DrawFrames(plan, first, count, 1,
             [&out](int, const cv::Mat& image) { out.push_back(image.clone()); });
  return out;
}

FootageResult RenderFootage(const FootageSpec& spec, const fs::path& out_dir, bool overwrite,
                            int jobs) {
  const auto start = std::chrono::steady_clock::now();
  if (!overwrite && fs::exists(out_dir))
    throw std::runtime_error("output folder '" + out_dir.string() +
                             "' exists (use --overwrite to replace it)");
  const FootagePlan plan = PlanFootage(spec);
  TemporaryFolder folder(out_dir, spec.codec == FootageCodec::kPng);
  ClipWriter writer(folder.path(), plan.truth);
  DrawFrames(plan, 0, static_cast<int>(plan.schedule.frames.size()), jobs,
             [&writer](int j, const cv::Mat& image) { writer.Write(j, image); });
  writer.Finish();
  io::WriteTextAtomically(folder.path() / "truth.json",
                          FootageTruthJson(plan.truth).dump(1) + "\n");
  folder.Commit(overwrite);
  FootageResult result;
  result.truth = plan.truth;
  result.path = out_dir;
  result.clip = out_dir / (spec.codec == FootageCodec::kH264 ? "clip.mp4" : "frames");
  result.render_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace hoof::synth
