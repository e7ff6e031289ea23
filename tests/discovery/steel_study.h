#pragma once
/// @file
/// A study of one steel surface for the discovery tests that work on a Workspace directly:
/// impacts at the given angles, speeds spread over 1.5-4 m/s, the measured velocities those of
/// the paper's model at (zeta, mu), and a measurement s.e. of 1e-4 of the impact speed per
/// component. A test replaces the measured velocities (SimulateStudy) as it needs.
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "discovery/internal.h"
#include "dynamics/parameters.h"

namespace hoof::discovery::internal {

inline void SteelStudy(Workspace& ws, const std::vector<double>& angles_deg, int per_angle,
                       double zeta, double mu, int threads = 2) {
  ws.surfaces = {"steel"};
  ws.k = {dynamics::PaperContact(dynamics::Surface::kSteel).k_N_m};
  ws.has_oblique = {false};
  ws.zeta_start = {zeta};
  ws.mu_start = {mu};
  ws.threads = threads;
  ws.measurement_floor = 1e-4;
  int fold = 0;
  for (double angle_deg : angles_deg)
    for (int k = 0; k < per_angle; ++k) {
      const double speed = 1.5 + 2.5 * k / (per_angle - 1);
      Obs o;
      o.surface = 0;
      o.angle_deg = angle_deg;
      o.speed_m_s = speed;
      o.normal = angle_deg == 0.0;
      ws.has_oblique[0] = ws.has_oblique[0] || !o.normal;
      o.phi = angle_deg * std::numbers::pi / 180.0;
      o.conditions = dynamics::ImpactConditions::Paper(speed, angle_deg);
      o.scale = speed;
      o.used = {!o.normal, true, !o.normal};
      o.measurement_var = Eigen::Vector3d::Constant(1e-8);
      o.fold = fold++ % 3;
      bool ok = false;
      o.measured = ws.Predict(o, zeta, mu, {}, &ok);
      EXPECT_TRUE(ok);
      ws.obs.push_back(o);
    }
  ws.mu_eff_max = MuEffMax(ws);
}

}  // namespace hoof::discovery::internal
