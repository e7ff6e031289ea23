// The joint arc fit (kinematics/flight_arcs.h) on closed-form bouncing balls
// (tests/support/bouncing_ball.h): which frame belongs to which arc, and what is left out and
// why, against the path's own truth; the shared acceleration and gravity's direction against
// the g and the camera roll the path was drawn with.
#include "kinematics/flight_arcs.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "support/bouncing_ball.h"

namespace hoof::kinematics {
namespace {

using testing::BallClip;
using testing::BallClipOptions;
using testing::MakeBallClip;

/// The arc a frame at time t belongs to in truth (its count of touches before t), or -1 when
/// the frame's time lies within a contact.
int TrueArc(const BallClip& clip, double t) {
  int k = 0;
  for (const auto& b : clip.bounces) {
    if (t >= b.t_touch && t <= b.t_sep) return -1;
    if (t > b.t_sep) ++k;
  }
  return k;
}

/// Four bounces at 30 fps from 0.8 m, frame 0 at a contact phase of 0.4 frame.
BallClipOptions FourBounces() {
  BallClipOptions o;
  o.fps = 30;
  o.frames = 60;
  o.phase_s = 0.4 / 30;
  o.e = {0.8, 0.7, 0.75, 0.6};
  o.mu = {0, 0, 0, 0};
  return o;
}

// Exact positions: five arcs, one per flight, every frame on its own arc, and the acceleration
// exactly gravity's.
TEST(FlightArcsTest, ExactPathsGiveEveryArcAndGravityExactly) {
  const BallClip clip = MakeBallClip(FourBounces());
  ASSERT_EQ(clip.bounces.size(), 4u);
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  ASSERT_EQ(A.arcs.size(), 5u);
  ASSERT_EQ(A.contacts.size(), 4u);
  EXPECT_NEAR(A.a_W.x(), 0.0, 1e-9);
  EXPECT_NEAR(A.a_W.y(), -9.81, 1e-9);
  EXPECT_NEAR(A.roll_deg, 0.0, 1e-7);
  for (std::size_t f = 0; f < clip.poses.size(); ++f) {
    EXPECT_EQ(A.frames[f].role, ArcFrameRole::kArc) << "frame " << f;
    EXPECT_EQ(A.frames[f].arc, TrueArc(clip, clip.poses[f].t_s)) << "frame " << f;
  }
  for (std::size_t k = 0; k < A.arcs.size(); ++k) EXPECT_TRUE(A.arcs[k].fitted);
}

// A rolled camera: "up" is fitted, not taken from the image, within its s.e. and a tenth of a
// degree; |a| within 3 s.e. of g. The noise level comes back from the residuals.
TEST(FlightArcsTest, ARolledCameraGivesGravitysDirection) {
  for (double roll : {-15.0, 12.0}) {
    SCOPED_TRACE("roll " + std::to_string(roll));
    BallClipOptions o = FourBounces();
    o.roll_deg = roll;
    o.noise_px = 0.5;
    o.seed = 3;
    const BallClip clip = MakeBallClip(o);
    const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
    ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
    EXPECT_EQ(A.contacts.size(), 4u);
    EXPECT_LT(std::abs(A.roll_deg - roll), 3 * A.roll_se_deg);
    EXPECT_LT(std::abs(A.roll_deg - roll), 0.1);
    EXPECT_LT(std::abs(A.a_norm - 9.81), 3 * A.a_norm_se);
    EXPECT_NEAR(A.sigma, 0.5 * o.m_per_px, 0.2 * 0.5 * o.m_per_px);
    EXPECT_FALSE(A.weighted);
  }
}

// Frames without a position and repeated frames are no samples, each named as such; the
// arcs and contacts are still found.
TEST(FlightArcsTest, MissingAndRepeatedFramesAreNoSamples) {
  BallClipOptions o = FourBounces();
  o.noise_px = 0.5;
  o.missing = {4, 17, 30};
  o.repeated = {9, 22, 41};
  const BallClip clip = MakeBallClip(o);
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  EXPECT_EQ(A.contacts.size(), 4u);
  for (int f : o.missing)
    EXPECT_EQ(A.frames[static_cast<std::size_t>(f)].role, ArcFrameRole::kNoSample);
  for (int f : o.repeated)
    EXPECT_EQ(A.frames[static_cast<std::size_t>(f)].role, ArcFrameRole::kRepeated);
  // Every other frame is a sample; at most one beside a contact may be left out as a contact
  // frame (the test beside a contact is at chi^2's 0.99 quantile).
  int contact = 0;
  for (const auto& fr : A.frames) {
    EXPECT_TRUE(fr.role == ArcFrameRole::kArc || fr.role == ArcFrameRole::kContact ||
                fr.role == ArcFrameRole::kNoSample || fr.role == ArcFrameRole::kRepeated)
        << ArcFrameRoleName(fr.role);
    contact += fr.role == ArcFrameRole::kContact;
  }
  EXPECT_LE(contact, 1);
  EXPECT_EQ(A.samples_used + contact, static_cast<int>(clip.poses.size()) - 6);
}

// A hand carries the ball down (a straight line, no gravity) and lets go three frames before
// the first touch: the frames in the hand are not in flight, the first arc starts at the
// release.
TEST(FlightArcsTest, FramesInAHandAreNotInFlight) {
  BallClipOptions o = FourBounces();
  o.noise_px = 0.5;
  o.release_s = 0.3;
  const double tau = 3.2 / o.fps, v_hand = 1.5;
  o.p0_G = {0, o.radius_m + v_hand * tau + 0.5 * 9.81 * tau * tau, 0};
  o.v0_G = {0.2, -v_hand, 0};
  const BallClip clip = MakeBallClip(o);
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  ASSERT_GE(A.contacts.size(), 1u);
  // The first touch comes at the release + tau; frames before the release are held.
  EXPECT_NEAR(clip.bounces[0].t_touch, o.release_s + tau, 1e-9);
  int held = 0;
  for (std::size_t f = 0; f < clip.poses.size(); ++f) {
    const double t = clip.poses[f].t_s;
    if (t < o.release_s - 1.5 / o.fps) {
      EXPECT_EQ(A.frames[f].role, ArcFrameRole::kNotInFlight) << "frame " << f;
      ++held;
    }
    if (t > o.release_s && t < clip.bounces[0].t_touch) {
      EXPECT_EQ(A.frames[f].role, ArcFrameRole::kArc) << "frame " << f;
    }
  }
  EXPECT_GE(held, 6);
  // The three frames after the release, and perhaps the one just before it (0.2 frame
  // periods early, its path within noise of the flight's).
  EXPECT_GE(A.arcs[0].n, 3);
  EXPECT_LE(A.arcs[0].n, 4);
}

// A contact lasting 12 ms with a frame inside it (the ball resting on the floor): that frame
// is a contact frame, left out; the other frames are on their arcs.
TEST(FlightArcsTest, AFrameOfTheBallOnTheFloorIsAContactFrame) {
  BallClipOptions o = FourBounces();
  o.noise_px = 0.3;
  o.contact_s = 0.012;
  // Frame 12 at 0.4 + 12 frames = 0.4133 s lies within the first contact (0.3954 + 4 ms on).
  o.phase_s = 0.0054;
  const BallClip clip = MakeBallClip(o);
  const double t_in = clip.bounces[0].t_touch + 0.006;
  std::size_t inside = clip.poses.size();
  for (std::size_t f = 0; f < clip.poses.size(); ++f)
    if (std::abs(clip.poses[f].t_s - t_in) < 0.006) inside = f;
  ASSERT_LT(inside, clip.poses.size()) << "no frame within the first contact";
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  EXPECT_EQ(A.frames[inside].role, ArcFrameRole::kContact);
  for (std::size_t f = 0; f < clip.poses.size(); ++f)
    if (f != inside && TrueArc(clip, clip.poses[f].t_s) >= 0) {
      EXPECT_EQ(A.frames[f].role, ArcFrameRole::kArc) << "frame " << f;
    }
}

// A frame far off its arc, away from any contact, is an outlier; the rest stay.
TEST(FlightArcsTest, AFrameOffItsArcIsAnOutlier) {
  BallClipOptions o = FourBounces();
  o.noise_px = 0.5;
  BallClip clip = MakeBallClip(o);
  clip.poses[25].p_WE += Eigen::Vector2d(0.02, -0.015);  // 17 px off
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  EXPECT_EQ(A.contacts.size(), 4u);
  EXPECT_EQ(A.frames[25].role, ArcFrameRole::kOutlier);
  EXPECT_GT(A.frames[25].residual_chi2, ArcOptions{}.outlier_chi2);
  int left_out = 0;
  for (const auto& fr : A.frames) left_out += fr.role != ArcFrameRole::kArc;
  EXPECT_EQ(left_out, 1);
}

// Six frames near the second arc's apex off it by 0.4 to 1.6 px, smoothly (a ball cut by the
// frame's edge, its edge fit pulled down as its top leaves the frame), 0.2 px noise at 60 fps,
// on 12 clips: those off by 7 noise s.d. or more are left out as outliers and the sweep goes
// on, so every contact after them is found and each frame outside the run is on its own arc.
// Allowed only the one or two outliers in a row (max_outlier_run 2), the sweep stops at the
// run on 7 of the 12 (the other starts of the sweep recover the rest on the others): asserted
// on at least 5.
TEST(FlightArcsTest, ARunOfFramesOffTheirArcNearAnApexAreOutliers) {
  int stopped = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    BallClipOptions o = FourBounces();
    o.fps = 60;
    o.frames = 120;
    o.phase_s = 0.4 / 60;
    o.noise_px = 0.2;
    o.seed = seed;
    BallClip clip = MakeBallClip(o);
    ASSERT_EQ(clip.bounces.size(), 4u);
    std::vector<std::size_t> second;
    for (std::size_t f = 0; f < clip.poses.size(); ++f)
      if (TrueArc(clip, clip.poses[f].t_s) == 1) second.push_back(f);
    ASSERT_GE(second.size(), 20u);
    const std::size_t first_off = second[second.size() / 2 - 3];
    const double off_px[] = {0.6, 1.3, 1.6, 1.5, 1.2, 0.4};
    for (std::size_t i = 0; i < 6; ++i)
      clip.poses[first_off + i].p_WE.y() -= off_px[i] * o.m_per_px;

    const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
    ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
    ASSERT_EQ(A.contacts.size(), 4u) << "seed " << seed;
    int contact = 0;
    for (std::size_t f = 0; f < clip.poses.size(); ++f) {
      if (f >= first_off && f < first_off + 6) {
        if (off_px[f - first_off] >= 7 * o.noise_px) {
          EXPECT_EQ(A.frames[f].role, ArcFrameRole::kOutlier) << "seed " << seed << " frame " << f;
        }
        continue;
      }
      if (A.frames[f].role == ArcFrameRole::kContact) {
        ++contact;
        continue;
      }
      EXPECT_EQ(A.frames[f].role, ArcFrameRole::kArc) << "seed " << seed << " frame " << f;
      EXPECT_EQ(A.frames[f].arc, TrueArc(clip, clip.poses[f].t_s))
          << "seed " << seed << " frame " << f;
    }
    EXPECT_LE(contact, 2) << "seed " << seed;
    for (const auto& arc : A.arcs) EXPECT_TRUE(arc.fitted) << "seed " << seed;

    ArcOptions two;
    two.max_outlier_run = 2;
    const FlightArcs B = FitFlightArcs(clip.poses, 0.0, 0.0, two);
    ASSERT_EQ(B.status, ArcFitStatus::kFitted) << B.message;
    stopped += B.contacts.size() < 4 && B.frames.back().role == ArcFrameRole::kNotInFlight;
  }
  EXPECT_GE(stopped, 5);
}

// Covariances given with the noise they describe (anisotropic: 1.5 px across, 0.5 px down):
// the fit is weighted and the factor fitted from the residuals is near 1; the acceleration
// stays within its s.e.
TEST(FlightArcsTest, CovariancesWeightTheFitAndTheirFactorIsFitted) {
  BallClipOptions o = FourBounces();
  o.seed = 5;
  BallClip clip = MakeBallClip(o);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  const double sx = 1.5 * o.m_per_px, sy = 0.5 * o.m_per_px;
  for (auto& p : clip.poses) {
    p.p_WE += Eigen::Vector2d(sx * n(rng), sy * n(rng));
    p.cov_p_WE = Eigen::Vector2d(sx * sx, sy * sy).asDiagonal();
  }
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  EXPECT_TRUE(A.weighted);
  EXPECT_NEAR(A.sigma, 1.0, 0.2);
  EXPECT_LT(std::abs(A.a_W.y() + 9.81), 3 * std::sqrt(A.cov_a_W(1, 1)));
}

// The fit is the weighted least-squares solution of its own design: with the roles and arcs it
// reports, a dense solve of every used frame's rows (whitened by its covariance's inverse
// Cholesky factor, its arc's position, velocity and the shared acceleration as columns) gives
// the same parameters, noise level and covariance. Correlated covariances and a frame knocked
// off its arc make the weights and the roles matter.
TEST(FlightArcsTest, TheFitIsTheDenseLeastSquaresSolutionOfItsDesign) {
  BallClipOptions o = FourBounces();
  o.seed = 7;
  BallClip clip = MakeBallClip(o);
  std::mt19937_64 rng(13);
  std::normal_distribution<double> n(0.0, 1.0);
  const double s = 0.7 * o.m_per_px;
  Eigen::Matrix2d cov;
  cov << 2.0 * s * s, 0.6 * s * s, 0.6 * s * s, 0.5 * s * s;
  const Eigen::Matrix2d L = cov.llt().matrixL();
  for (auto& p : clip.poses) {
    p.p_WE += L * Eigen::Vector2d(n(rng), n(rng));
    p.cov_p_WE = cov;
  }
  clip.poses[20].p_WE.x() += 40 * s;
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  ASSERT_EQ(A.status, ArcFitStatus::kFitted) << A.message;
  ASSERT_TRUE(A.weighted);
  EXPECT_EQ(A.frames[20].role, ArcFrameRole::kOutlier);
  const auto P = A.x.size();
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < A.frames.size(); ++i)
    if (A.frames[i].role == ArcFrameRole::kArc &&
        A.slot[static_cast<std::size_t>(A.frames[i].arc)] >= 0)
      used.push_back(i);
  ASSERT_EQ(static_cast<int>(used.size()), A.samples_used);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(2 * static_cast<Eigen::Index>(used.size()), P);
  Eigen::VectorXd b(D.rows());
  const Eigen::Matrix2d W = L.inverse();
  for (std::size_t r = 0; r < used.size(); ++r) {
    const std::size_t i = used[r];
    const auto k = static_cast<std::size_t>(A.frames[i].arc);
    const double tau = clip.poses[i].t_s - A.arcs[k].t_ref_s;
    const auto row = 2 * static_cast<Eigen::Index>(r);
    D.block(row, 4 * A.slot[k], 2, 2) = W;
    D.block(row, 4 * A.slot[k] + 2, 2, 2) = W * tau;
    D.block(row, P - 2, 2, 2) = W * (0.5 * tau * tau);
    b.segment<2>(row) = W * clip.poses[i].p_WE;
  }
  const Eigen::VectorXd x = D.colPivHouseholderQr().solve(b);
  const double s2 = (b - D * x).squaredNorm() / static_cast<double>(D.rows() - P);
  const Eigen::MatrixXd C = s2 * (D.transpose() * D).inverse();
  EXPECT_EQ(A.dof, D.rows() - P);
  EXPECT_NEAR(A.sigma, std::sqrt(s2), 1e-9 * std::sqrt(s2));
  for (Eigen::Index i = 0; i < P; ++i) {
    EXPECT_NEAR(A.x(i), x(i), 1e-9 * std::max(1.0, std::abs(x(i)))) << "parameter " << i;
    for (Eigen::Index j = 0; j < P; ++j)
      EXPECT_NEAR(A.cov_x(i, j), C(i, j), 1e-8 * std::sqrt(C(i, i) * C(j, j)))
          << "covariance " << i << ", " << j;
  }
}

TEST(FlightArcsTest, TooFewFramesAndBadOptions) {
  BallClip clip = MakeBallClip(FourBounces());
  clip.poses.resize(3);
  const FlightArcs A = FitFlightArcs(clip.poses, 0.0, 0.0);
  EXPECT_EQ(A.status, ArcFitStatus::kTooFewFrames);
  EXPECT_NE(A.message.find("4 or more frames"), std::string::npos) << A.message;
  ArcOptions bad;
  bad.min_arc_frames = 2;
  EXPECT_THROW(FitFlightArcs(clip.poses, 0.0, 0.0, bad), std::invalid_argument);
  bad = ArcOptions{};
  bad.max_excluded_fraction = 1.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
  bad = ArcOptions{};
  bad.max_outlier_run = 1;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::kinematics
