#pragma once
/// @file
/// A ball's spin from its own texture (docs/tracking.md, "Spin from a ball's texture"): a ball
/// has no markers, but stripes, a drawn cross or a logo on it turn with it. The face of the ball
/// is sampled on rings about its fitted centre in each frame; what does not turn with the ball
/// is taken out of each ring (its mean, and the first harmonic along the ring that a light
/// from one side paints on a sphere; the brightest pixels, a specular highlight, are left out);
/// the rotation between two frames is the circular shift along the rings that best correlates
/// their faces. Over a free-flight arc the spin is constant, so one angular velocity is fitted
/// to all the arc's frame pairs at once, which also settles a pattern that repeats around the
/// ball (stripes look alike after half a turn) as long as it turns by less than half its
/// period from frame to frame.
///
/// The rotation measured is about the camera's axis: the spin of a ball moving in the image
/// plane. Angles are in the image (x right, y down): positive turns x toward y, clockwise as
/// the frames are shown; in W (y up) the same spin is negative.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace hoof::tracking {

/// Settings of the spin measurement.
struct BallSpinOptions {
  /// The rings sampled, as fractions of the fitted radius: the centre (a few pixels, where a
  /// turn moves nothing) and the limb (darkened, blurred by the edge) are left out;
  /// 0 <= inner < outer <= 1.
  double inner_fraction = 0.2, outer_fraction = 0.8;
  int rings = 8;  ///< rings between them; in [1, 64]
  /// A ball of a smaller radius (px) is not sampled: its rings lie less than a pixel apart,
  /// and on rendered clips at 640 x 360 (a 20 px ball) the spins that passed the other tests
  /// followed its smeared outline, not its paint; >= 3.
  double min_radius_px = 12.0;
  /// Samples around each ring; a power of two in [16, 1024] (the correlation is circular).
  int angles = 128;
  /// Pixels of the face brighter than this quantile of it are left out: a specular highlight
  /// stays where the light is while the ball turns; in (0.5, 1].
  double highlight_quantile = 0.97;
  /// A face counts as textured when its texture's standard deviation (after the shading is
  /// taken out) exceeds this many times the frame noise; > 0.
  double min_texture_to_noise = 4.0;
  /// Fewest frame pairs an arc's spin is fitted to: with fewer, the aliases of a repeating
  /// pattern and the shading that stays put are not told apart from the turn; >= 1.
  int min_pairs = 5;
  /// The mean of an arc's faces, what does not turn with the ball, is taken out of each before
  /// they are compared where the arc has at least this many textured faces; >= 2.
  int min_static_faces = 4;
  /// Of the spins whose summed correlation lies within this fraction of the best one's (the
  /// aliases of a pattern that repeats around the ball), the slowest is taken; in [0, 1).
  double alias_margin = 0.1;
  /// The arc's spin is measured only where its faces, turned by it, correlate at least this
  /// well on average (normalised, after the mean face is taken out): below it what differs
  /// between frames is noise and compression, not a texture turning; in [0, 1).
  double min_mean_peak = 0.3;
  /// Throws std::invalid_argument naming the field.
  void Validate() const;
};

/// The ball's face in one frame: its texture on rings about the centre, with what does not
/// turn with the ball taken out. `rings` rows by `angles` columns, row r at radius
/// (inner + (outer - inner) (r + 0.5) / rings) of the fitted radius, column k at angle
/// 2 pi k / angles from the image's +x toward +y.
struct BallFace {
  bool textured = false;           ///< enough texture to measure a turn (see options)
  std::string why;                 ///< why not textured
  cv::Mat texture;                 ///< CV_32F, rings x angles; 0 where left out
  cv::Mat weight;                  ///< CV_32F, 1 where sampled, 0 where left out
  double texture_sd = 0.0;         ///< of the texture samples (frame units, [0, 1])
  double noise_sd = 0.0;           ///< the frame's noise near the ball (frame units, [0, 1])
  Eigen::Vector2d centre_I{0, 0};  ///< where it was sampled (px)
  double radius_px = 0.0;
};

/// Samples the face of a ball of radius `radius_px` centred at `centre_I` in `grey` (one
/// channel, any depth; values scaled to [0, 1] as tracking::ToUnitFloat does).
/// `noise_sd` is the frame's noise standard deviation in those units (0: measured here from
/// the face's own neighbour differences).
BallFace SampleBallFace(const cv::Mat& grey, const Eigen::Vector2d& centre_I, double radius_px,
                        double noise_sd, const BallSpinOptions& options = {});

/// The correlation of face `b` with face `a` turned by each of the `angles` shifts: entry k
/// is for a turn of 2 pi k / angles (image sense) from a to b, normalised to [-1, 1].
std::vector<double> FaceCorrelation(const BallFace& a, const BallFace& b);

/// The turn from `a` to `b` (rad, image sense, in (-pi, pi]) that best correlates them, refined
/// between samples, and the height of that peak (normalised correlation).
struct FaceTurn {
  double turn_I_rad = 0.0;
  double peak = 0.0;
};
FaceTurn BestTurn(const std::vector<double>& correlation);

/// One free-flight arc's spin.
struct ArcSpin {
  bool measured = false;
  std::string why;         ///< why not measured
  double w_I_rad_s = 0.0;  ///< d(angle)/dt in the image sense (rad/s)
  double w_se_rad_s = 0.0;
  int pairs = 0;           ///< frame pairs fitted
  double mean_peak = 0.0;  ///< mean correlation at the fitted turns
};

/// The constant spin that best explains the turns between consecutive faces of one arc:
/// `faces[i]` taken at `t_s[i]` (increasing). Pairs whose faces are both textured take part,
/// with the arc's mean face taken out of each (options.min_static_faces). The spin is searched
/// over every rate that turns the ball by less than half a turn between the closest frames (the
/// sum of the pairs' correlations at the turn each rate predicts; of the aliases within
/// options.alias_margin of the best, the slowest), refined, and its standard error taken from
/// the scatter of the pairs' own best turns about it (each pair's error at least a sample's
/// rounding, 2 pi / angles / sqrt 12, so that pairs that agree exactly do not claim an error of
/// 0). Not measured with fewer than options.min_pairs such pairs, or where the turned faces
/// correlate below options.min_mean_peak on average.
ArcSpin FitArcSpin(const std::vector<BallFace>& faces, const std::vector<double>& t_s,
                   const BallSpinOptions& options = {});

}  // namespace hoof::tracking
