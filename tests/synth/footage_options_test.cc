// The everyday-footage options (synth/footage_options.h): each bad value is refused with a
// message that names its field; the presets and names round-trip.
#include "synth/footage_options.h"

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::synth {
namespace {

/// The message of spec.Validate(), or "" when it passes.
std::string Refusal(const FootageSpec& spec) {
  try {
    spec.Validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(FootageOptionsTest, TheDefaultsAreValidAndEveryBadValueNamesItsField) {
  EXPECT_EQ(Refusal(FootageSpec{}), "");
  for (auto s : {FootageScenario::kBounce, FootageScenario::kNeverLands, FootageScenario::kStill,
                 FootageScenario::kHandOnly})
    EXPECT_EQ(Refusal(DefaultFootageSpec(s)), "") << ToString(s);
  const std::vector<std::pair<std::string, std::function<void(FootageSpec&)>>> cases = {
      {"ball.radius_m", [](FootageSpec& s) { s.ball.radius_m = 0.5; }},
      {"ball.shininess", [](FootageSpec& s) { s.ball.shininess = 0; }},
      {"launch.drop_height_m", [](FootageSpec& s) { s.launch.drop_height_m = -0.1; }},
      {"launch.v_W_m_s", [](FootageSpec& s) { s.launch.v_W_m_s.y() = 25; }},
      {"launch.w_W_rad_s", [](FootageSpec& s) { s.launch.w_W_rad_s.x() = std::nan(""); }},
      {"launch.release_time_s", [](FootageSpec& s) { s.launch.release_time_s = 3; }},
      {"bounce.e_mean", [](FootageSpec& s) { s.bounce.e_mean = 1.0; }},
      {"bounce.e_sd", [](FootageSpec& s) { s.bounce.e_sd = -0.1; }},
      {"bounce.mu", [](FootageSpec& s) { s.bounce.mu = 3; }},
      {"camera.width_px", [](FootageSpec& s) { s.camera.width_px = 8; }},
      {"camera.height_px", [](FootageSpec& s) { s.camera.height_px = 181; }},  // odd: H.264
      {"camera.horizontal_fov_deg", [](FootageSpec& s) { s.camera.horizontal_fov_deg = 170; }},
      {"camera.rotation_tag_deg", [](FootageSpec& s) { s.camera.rotation_tag_deg = 45; }},
      {"camera.rotation_tag_deg",
       [](FootageSpec& s) {
         s.camera.rotation_tag_deg = 90;
         s.codec = FootageCodec::kPng;
       }},
      {"camera.p_W_m", [](FootageSpec& s) { s.camera.p_W_m.z() = -0.1; }},
      {"room.wall_z_m", [](FootageSpec& s) { s.room.wall_z_m = 0.2; }},
      {"room.light_p_W_m", [](FootageSpec& s) { s.room.light_p_W_m.y() = 0.0; }},
      {"room.ambient", [](FootageSpec& s) { s.room.ambient = 1.5; }},
      {"launch.z_m", [](FootageSpec& s) { s.launch.z_m = -0.59; }},  // into the back wall
      {"hand.leave_direction", [](FootageSpec& s) { s.hand.leave_direction.setZero(); }},
      {"timing.capture_fps", [](FootageSpec& s) { s.timing.capture_fps = 0; }},
      {"timing.exposure_s", [](FootageSpec& s) { s.timing.exposure_s = 0.1; }},
      {"timing.duration_s", [](FootageSpec& s) { s.timing.duration_s = 500; }},
      {"timing.drop_frames",
       [](FootageSpec& s) {
         s.timing.drop_frames = 1;
         s.timing.delivery = FrameDelivery::kLatestCapture;
       }},
      {"timing.repeat_frames", [](FootageSpec& s) { s.timing.repeat_frames = -1; }},
      {"sensor.max_blur_samples", [](FootageSpec& s) { s.sensor.max_blur_samples = 0; }},
      {"png_compression", [](FootageSpec& s) { s.png_compression = 10; }},
  };
  for (const auto& [field, spoil] : cases) {
    FootageSpec s;
    spoil(s);
    const std::string message = Refusal(s);
    EXPECT_NE(message.find("FootageSpec." + field), std::string::npos)
        << field << ": '" << message << "'";
  }
}

TEST(FootageOptionsTest, NamesAndPresets) {
  for (auto c : {BallColor::kRed, BallColor::kYellow, BallColor::kOrange, BallColor::kWhite,
                 BallColor::kGreen, BallColor::kBlue})
    EXPECT_EQ(ParseBallColor(ToString(c)), c);
  EXPECT_EQ(ParseFootageScenario("never-lands"), FootageScenario::kNeverLands);
  EXPECT_EQ(ParseFrameDelivery("latest-capture"), FrameDelivery::kLatestCapture);
  EXPECT_THROW(ParseBallColor("purple"), std::invalid_argument);
  EXPECT_THROW(ParseFootageCodec("gif"), std::invalid_argument);
  const FootageTimingOptions slow = TimingOf(TimingPreset::kSlowMotion);
  EXPECT_EQ(slow.capture_fps, 240);
  EXPECT_EQ(ContainerFps(slow), 30);
  EXPECT_NEAR(ExposureSeconds(slow), 1.0 / 480, 1e-15);
  const FootageTimingOptions phone = TimingOf(TimingPreset::kPhone);
  EXPECT_EQ(ContainerFps(phone), 30);  // 0 means the capture rate
  EXPECT_NEAR(InertiaFactor(BallInertia::kHollow), 2.0 / 3.0, 1e-15);
}

}  // namespace
}  // namespace hoof::synth
