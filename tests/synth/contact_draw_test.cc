// The per-trial draws of e and mu have the paper's means and spreads (SCIENCE.md section 4),
// and the drawn e becomes the (k, b) that gives it, by the closed form written out here.
#include "synth/contact_draw.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::synth {
namespace {

struct Case {
  dynamics::Surface surface;
  double e_mean;   // closed-form e of the paper's (k, b): SCIENCE.md section 4's table
  double e_sd;     // the paper's measured s.d.
  double mu_mean;  // the paper's mu_eff at 30 deg
};

/// Mean and s.d. of N(mu, sd) truncated to [lo, hi] (the textbook truncated-normal moments).
std::pair<double, double> TruncatedMoments(double mu, double sd, double lo, double hi) {
  const auto pdf = [](double x) { return std::exp(-x * x / 2) / std::sqrt(2 * M_PI); };
  const auto cdf = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  const double a = (lo - mu) / sd, b = (hi - mu) / sd, z = cdf(b) - cdf(a);
  const double mean = mu + sd * (pdf(a) - pdf(b)) / z;
  const double var =
      sd * sd * (1 + (a * pdf(a) - b * pdf(b)) / z - std::pow((pdf(a) - pdf(b)) / z, 2));
  return {mean, std::sqrt(var)};
}

double ClosedFormE(double z) {
  if (z < 1) return std::exp(-z / std::sqrt(1 - z * z) * std::atan(std::sqrt(1 - z * z) / z));
  // Overdamped (wn = 1, v = 1): depth x(t) = (exp(s1 t) - exp(s2 t)) / (s1 - s2); compression
  // ends where x' = 0 (found here by bisection), and the elastic return gives e = x(t_m).
  const double q = std::sqrt(z * z - 1), s1 = -z + q, s2 = -z - q;
  auto rate = [&](double t) { return (s1 * std::exp(s1 * t) - s2 * std::exp(s2 * t)) / (s1 - s2); };
  double lo = 0, hi = 1;
  while (rate(hi) > 0) hi *= 2;
  for (int i = 0; i < 200; ++i) (rate(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  const double t = 0.5 * (lo + hi);
  return (std::exp(s1 * t) - std::exp(s2 * t)) / (s1 - s2);
}

TEST(ContactDrawTest, DrawsHaveThePapersMeansAndSpreads) {
  constexpr int kN = 400;
  const dynamics::SpecimenParameters specimen;
  for (const Case& c : {Case{dynamics::Surface::kSteel, 0.8502, 0.041, 0.19},
                        Case{dynamics::Surface::kConcrete, 0.7089, 0.039, 0.30},
                        Case{dynamics::Surface::kAsphalt, 0.4984, 0.071, 0.34}}) {
    std::vector<double> e, mu;
    for (int i = 0; i < kN; ++i) {
      TrialSpec spec;
      spec.surface = c.surface;
      std::mt19937_64 rng(1000 + static_cast<std::uint64_t>(i));
      const ContactDraw d = DrawContact(spec, specimen, rng);
      e.push_back(d.e_drawn);
      mu.push_back(d.contact.mu);
      // The drawn e is what the two-phase law gives for the (k, b) set from it.
      const double zeta = d.contact.b_N_s_m / (2 * std::sqrt(d.contact.k_N_m * specimen.mass_kg));
      ASSERT_NEAR(ClosedFormE(zeta), d.e_drawn, 1e-9);
      ASSERT_EQ(d.contact.k_N_m, dynamics::PaperContact(c.surface).k_N_m);
    }
    const auto stats = [](const std::vector<double>& x) {
      double m = 0, v = 0;
      for (double xi : x) m += xi;
      m /= static_cast<double>(x.size());
      for (double xi : x) v += (xi - m) * (xi - m);
      return std::pair{m, std::sqrt(v / static_cast<double>(x.size() - 1))};
    };
    const auto [e_mean, e_sd] = stats(e);
    const auto [mu_mean, mu_sd] = stats(mu);
    // Mean: within 4 standard errors sd / sqrt(n). S.d.: its standard error for a normal
    // sample is sd / sqrt(2 (n - 1)); again 4 of them. (The seeds are fixed; 4 SE would fail
    // by chance with probability 6e-5 for another seed set.)
    // e is drawn from N(mean, sd) kept within [0.05, 0.99]: compare with the truncated-normal
    // moments (only steel's upper bound, 3.4 s.d. out, moves them, by about 1e-4).
    const double n = kN;
    const auto [e_expected, e_sd_expected] = TruncatedMoments(c.e_mean, c.e_sd, 0.05, 0.99);
    EXPECT_NEAR(e_mean, e_expected, 4 * e_sd_expected / std::sqrt(n))
        << dynamics::SurfaceName(c.surface);
    EXPECT_NEAR(e_sd, e_sd_expected, 4 * e_sd_expected / std::sqrt(2 * (n - 1)))
        << dynamics::SurfaceName(c.surface);
    EXPECT_NEAR(e_expected, c.e_mean, 2e-4);
    EXPECT_NEAR(e_sd_expected, c.e_sd, 2e-4);
    EXPECT_NEAR(mu_mean, c.mu_mean, 4 * kFrictionSpread / std::sqrt(n));
    EXPECT_NEAR(mu_sd, kFrictionSpread, 4 * kFrictionSpread / std::sqrt(2 * (n - 1)));
  }
}

TEST(ContactDrawTest, FixedValuesAndNoScatterUseThePapersCoefficients) {
  const dynamics::SpecimenParameters specimen;
  std::mt19937_64 rng(5);
  TrialSpec spec;
  spec.surface = dynamics::Surface::kConcrete;
  spec.scatter_parameters = false;
  ContactDraw d = DrawContact(spec, specimen, rng);
  EXPECT_EQ(d.contact.b_N_s_m, 932.20);
  EXPECT_EQ(d.contact.mu, 0.30);
  spec.e = 0.6;
  spec.mu = 0.25;
  spec.hidden.contact.rolling_resistance_m = 1e-4;
  d = DrawContact(spec, specimen, rng);
  const double zeta = d.contact.b_N_s_m / (2 * std::sqrt(d.contact.k_N_m * specimen.mass_kg));
  EXPECT_NEAR(ClosedFormE(zeta), 0.6, 1e-9);
  EXPECT_EQ(d.contact.mu, 0.25);
  EXPECT_EQ(d.contact.extensions.rolling_resistance_m, 1e-4);
}

}  // namespace
}  // namespace hoof::synth
