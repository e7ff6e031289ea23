#pragma once
/// @file
/// Simulation meets measurement (docs/science.md, "The rigid-body model"; docs/tracking.md,
/// "4. Kinematics"): the contact law fitted per surface to the measured trials, every trial
/// simulated from its measured state before the impact, sampled at the frame times and compared
/// frame by frame and in its velocities after the impact.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "dynamics/contact_fit.h"
#include "dynamics/impact_simulator.h"
#include "pipeline/trial_analysis.h"

namespace hoof::compare {

/// The mass that stands in for a body whose mass is unknown (a ball without a specimen): the
/// paper's specimen's 8 g, the mass for which each surface's k is the paper's, so that contact
/// durations stay the paper's. No velocity depends on it: with b = 2 zeta sqrt(k m) the normal
/// contact depends on zeta and sqrt(k / m) only, and the friction's effect on I / (m R^2).
inline constexpr double kReferenceMass_kg = 0.008;

/// The body a trial is simulated as, and what of it had to be assumed.
struct SimulatedBody {
  dynamics::SpecimenParameters specimen;
  /// False: the mass is unknown and kReferenceMass_kg stands in; kinetic energies and the
  /// contact law's k and b then are not the body's.
  bool mass_known = true;
  /// A ball of unknown inertia (no specimen) is simulated as a solid sphere, I = 2/5 m R^2;
  /// only its tangential velocity after a contact that sticks depends on that.
  bool inertia_assumed = false;
};

/// The body trial `t` is simulated as: its specimen, or for a ball of unknown mass a solid
/// sphere of kReferenceMass_kg and its radius.
SimulatedBody BodyToSimulate(const pipeline::TrialAnalysis& trial);

/// The contact law of one surface, as the study's measurements determine it.
struct SurfaceModel {
  std::string surface;
  int normal_trials = 0;
  int oblique_trials = 0;
  /// False when a trial on the surface has no known mass (a ball without a specimen): k and b
  /// are then those of kReferenceMass_kg, which the simulation uses and the study file and the
  /// report do not give as the body's (NaN, "needs the mass").
  bool mass_known = true;
  /// zeta from the normal trials (velocities determine zeta only; see dynamics/contact_fit.h).
  dynamics::ContactFitSummary zeta_fit;
  /// k: not identified by velocities. The paper's k for steel, concrete and asphalt, else
  /// 1e8 N/m; any k of the valley gives the same velocities (to < 1e-3).
  double k_N_m = 0.0;
  double b_N_s_m = 0.0;  ///< 2 zeta sqrt(k m)
  /// mu by the stated rule: the value that minimizes the squared, standard-error-weighted
  /// differences between measured and simulated tangential velocity of C and spin after the
  /// impact (the two quantities friction drives), over the surface's oblique trials, each
  /// simulated from its measured state before impact. Searched on a 0.01 grid over [0, 1.5],
  /// then refined (Brent).
  double mu = 0.0;
  /// From the curvature of that sum of squares, scaled by the reduced chi-square when it
  /// exceeds 1 (trials scatter more than their measurement errors); NaN when undefined.
  double mu_se = 0.0;
  /// True when every mu above the estimate fits as well (within 1 of the minimum sum): the
  /// contacts stick, and the data bound mu only from below.
  bool mu_only_lower_bound = false;
  bool success = false;
  std::string message;
  /// The contact parameters to simulate this surface's trials with.
  dynamics::ContactParameters Contact() const { return {k_N_m, b_N_s_m, mu}; }
};

/// One frame: the simulation against the measurement.
struct FrameComparison {
  double t_s = 0.0;                ///< frame time since frame 0
  Eigen::Vector2d p_WC_sim{0, 0};  ///< simulated centre of mass (m)
  double theta_W_sim_rad = 0.0;
  bool measured = false;  ///< the frame has a measured pose
  Eigen::Vector2d p_WC_meas{0, 0};
  double theta_W_meas_rad = 0.0;
  std::vector<Eigen::Vector2d> markers_W_sim;    ///< simulated marker centres in W (m)
  std::vector<Eigen::Vector2d> markers_px_sim;   ///< per layout marker
  std::vector<Eigen::Vector2d> markers_px_meas;  ///< NaN where not found
  std::vector<double> marker_residual_px;        ///< |measured - simulated|, NaN where not found
  /// The centre of mass C in the image (px): simulated, measured (from the measured pose; NaN
  /// where the frame has none) and |measured - simulated|: the one residual of a body without
  /// markers (a ball, an outline), and of a marked one too.
  Eigen::Vector2d centre_px_sim{0, 0};
  Eigen::Vector2d centre_px_meas{core::kNaN, core::kNaN};
  double centre_residual_px = core::kNaN;
  double kinetic_energy_sim_J = 0.0;
};

/// A trial compared with its simulation.
struct TrialComparison {
  bool success = false;
  std::string message;
  double t_touch_s = 0.0;  ///< first touch of the simulation, since frame 0
  dynamics::ImpactResult sim;
  /// Velocities after the impact at the measured impact time, in S: measured, simulated, and
  /// the standard error of the simulated value propagated from the measured state before.
  Eigen::Vector2d v_SC_after_meas{0, 0}, v_SC_after_sim{0, 0}, v_SC_after_sim_se{0, 0};
  double w_after_meas = 0.0, w_after_sim = 0.0, w_after_sim_se = 0.0;
  /// Residual / combined standard error (measured and propagated), per component.
  Eigen::Vector2d v_SC_after_z{0, 0};
  double w_after_z = 0.0;
  /// Kinetic energies (J); NaN where the mass is unknown (SimulatedBody::mass_known).
  double kinetic_energy_before_J = 0.0, kinetic_energy_after_meas_J = 0.0,
         kinetic_energy_after_sim_J = 0.0;
  bool mass_known = true;        ///< SimulatedBody::mass_known of the trial
  bool inertia_assumed = false;  ///< SimulatedBody::inertia_assumed of the trial
  std::vector<FrameComparison> frames;
  /// Kinetic energy through the contact (paper Figure 8): times since first touch and values.
  std::vector<double> contact_t_s, contact_kinetic_energy_J;
};

/// Initial conditions at first touch from a measured trial, and the touch time: the before-fit
/// carried to the time at which the simulated before and after flights meet where the measured
/// fits meet. Used by CompareTrial.
dynamics::ImpactConditions MeasuredConditions(const pipeline::TrialAnalysis& trial,
                                              double t_touch_s);

/// Standard errors of the fitted model parameters, carried into the simulated values' errors.
struct ModelUncertainty {
  double zeta_se = 0.0;
  double mu_se = 0.0;
};

/// Simulates `trial` (which must have succeeded) with `contact` from its measured state and
/// compares. The simulated values' standard errors combine the measured state's before the
/// impact with `uncertainty` (one-sided differences of one standard error each). Failures come
/// back in success/message.
TrialComparison CompareTrial(const pipeline::TrialAnalysis& trial,
                             const dynamics::ContactParameters& contact,
                             const ModelUncertainty& uncertainty = {});

/// The uncertainty of a fitted surface model (NaN errors count as 0).
ModelUncertainty Uncertainty(const SurfaceModel& model);

/// The markers a trial's comparison carries, in layout order: its specimen's, where it is
/// tracked by its markers; none for a body tracked by its silhouette (a ball, or an outline
/// whose study.json may still list the layout of a marked specimen it has not got).
std::vector<std::pair<std::string, Eigen::Vector2d>> ComparedMarkers(
    const pipeline::TrialAnalysis& trial);

/// The trial's specimen as the simulator wants it (BodyToSimulate's).
dynamics::SpecimenParameters SpecimenOf(const pipeline::TrialAnalysis& trial);

/// First-touch time (since frame 0) at which `contact` makes the simulated flights before and
/// after the impact meet where the measured fits meet (CompareTrial's rule).
double SimulatedTouchTime(const pipeline::TrialAnalysis& trial,
                          const dynamics::ContactParameters& contact);

/// Simulated velocity of C in S and spin after the impact, carried under gravity to the
/// measured impact time, for a simulation `result` that started at `t_touch_s`.
std::pair<Eigen::Vector2d, double> SimulatedAfterAtImpactTime(const pipeline::TrialAnalysis& trial,
                                                              const dynamics::ImpactResult& result,
                                                              double t_touch_s);

/// Fits the contact law of `surface` to the successful trials among `trials` on it. `jobs`
/// threads (0 = all cores) evaluate the grid in mu; the result is the same for any number.
SurfaceModel FitSurfaceModel(const std::string& surface,
                             const std::vector<pipeline::TrialAnalysis>& trials, int jobs = 1);

}  // namespace hoof::compare
