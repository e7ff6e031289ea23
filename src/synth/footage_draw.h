#pragma once
/// @file
/// Draws the captures of an everyday clip (docs/synthetic-trials.md, "Everyday footage"): the
/// room (drawn once), the ball's soft shadow on the contact surface, the ball (ray-cast sphere:
/// Lambert shading and a Blinn-Phong highlight from the ceiling light, its texture turning with
/// its orientation, 4 x 4 rays on its rim), the hand in front, all averaged over sub-frame
/// samples of the exposure (motion blur, across a bounce too), then vignetting, sRGB, and read
/// and shot noise. It draws; it never detects.

#include <vector>

#include <opencv2/core.hpp>

#include "synth/ball_flight.h"
#include "synth/footage_plan.h"

namespace hoof::synth {

/// Renders captures of one clip. Holds the room's image; Render is const and may be called
/// from several threads at once.
class FootageFrameRenderer {
 public:
  /// Draws the room (on `jobs` threads, 0 = all cores); `plan` must outlive the renderer.
  explicit FootageFrameRenderer(const FootagePlan& plan, int jobs = 1);
  /// Capture `capture` as delivered (upright): CV_8UC3, BGR. Its noise is seeded by the spec's
  /// seed and the capture, so a repeated frame is the same image.
  cv::Mat Render(int capture) const;
  /// The room alone, linear BGR (CV_32FC3).
  const cv::Mat& room_linear() const { return room_.linear; }

 private:
  struct Sample;
  Sample MakeSample(double t_s) const;
  cv::Rect SampleBounds(const Sample& s) const;
  void DrawShadow(const Sample& s, const cv::Rect& roi, cv::Mat& linear) const;
  /// `sharp`: 4 x 4 rays on the rim (else coverage from the distance to the rim).
  void DrawBall(const Sample& s, const cv::Rect& roi, bool sharp, cv::Mat& linear) const;
  void DrawHand(const Sample& s, const cv::Rect& roi, cv::Mat& linear) const;
  cv::Vec3f BallColour(const Sample& s, double x_px, double y_px) const;
  void ToSrgb(const cv::Mat& linear, const cv::Rect& roi, cv::Mat& srgb) const;
  void AddNoise(int capture, cv::Mat& srgb) const;

  const FootagePlan& plan_;
  const FootageSpec& spec_;
  const PinholeCamera& camera_;
  const BallPath& path_;
  const HandModel& hand_;
  const FrameSchedule& schedule_;
  const RoomLight& light_;
  RoomImage room_;
  cv::Mat gain_;       ///< CV_32FC3 vignetting gain.
  cv::Mat room_srgb_;  ///< CV_32FC3 sRGB levels (0..255) of the room with vignetting.
  std::vector<float> srgb_lut_;
  Eigen::Vector3d albedo_bgr_;
};

/// The sRGB level (0..255) of a linear value (IEC 61966-2-1), clamped to [0, 1] first.
double LinearToSrgbLevel(double linear);

}  // namespace hoof::synth
