// The candidate library, the names of the workflow's enums, and option checks
// (docs/discovery.md).
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "discovery/internal.h"

namespace hoof::discovery {
namespace internal {

const LibraryEntry& Entry(const std::string& key) {
  for (const auto& e : Library())
    if (e.key == key) return e;
  throw std::invalid_argument("candidates: unknown effect '" + key + "'");
}

CandidateResult CandidateOf(const std::string& key) {
  const LibraryEntry& e = Entry(key);
  CandidateResult c;
  c.key = key;
  c.name = e.name;
  c.parameter = e.parameter;
  c.unit = e.unit;
  c.measurement_effect = e.measurement_effect;
  c.detection_limit = std::numeric_limits<double>::quiet_NaN();
  return c;
}

void Apply(const std::string& key, double value, dynamics::ContactExtensions& x) {
  if (key == "hunt_crossley")
    x.hunt_crossley_N_s_m2 = value;
  else if (key == "hertz_stiffness")
    x.stiffness_exponent_extra = value;
  else if (key == "plastic_unloading")
    x.unloading_stiffness_ratio = value;
  else if (key == "static_friction")
    x.static_friction_excess = value;
  else if (key == "tangential_compliance")
    x.tangential_compliance_ratio = value;
  else if (key == "rolling_resistance")
    x.rolling_resistance_m = value;
  else
    throw std::invalid_argument("no contact extension for '" + key + "'");
}

std::string Fmt(double v, int precision) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

std::string UnitSuffix(const std::string& unit) {
  return unit == "1" || unit.empty() ? "" : " " + unit;
}

std::string Percent(double fraction) {
  if (!std::isfinite(fraction)) return "n/a";
  std::ostringstream s;
  s << std::fixed;
  s.precision(0);
  // No "-0" for a shrink that rounds to nothing.
  s << (std::abs(100 * fraction) < 0.5 ? 0.0 : 100 * fraction);
  return s.str();
}

std::string FmtP(double p) {
  if (p < 1e-300) return "< 1e-300";
  std::ostringstream s;
  s.precision(2);
  if (p < 1e-3) s << std::scientific;
  s << p;
  return s.str();
}

}  // namespace internal

using internal::Fmt;

const std::vector<LibraryEntry>& Library() {
  static const std::vector<LibraryEntry> library = {
      {"hunt_crossley", "velocity-dependent (Hunt-Crossley) damping", "c", "N s/m^2", 2e7, 5e8,
       false, "extra damping c |delta| delta' in compression: e falls as the impact speed rises",
       "impacts over a wider range of speeds, or the force through the contact (its hysteresis "
       "loop grows with speed)"},
      {"hertz_stiffness", "nonlinear (Hertzian) stiffness", "p", "1", 0.5, 1.0, false,
       "elastic force k |delta| (|delta| / delta_ref)^p: the effective damping ratio changes with "
       "speed, e rises with speed",
       "the contact duration against impact speed (it shortens with speed only for a stiffening "
       "contact), or the force through the contact"},
      {"plastic_unloading", "dissipative (plastic) restitution", "r", "1", 0.5, 10.0, false,
       "unloading stiffer than loading, k (1 + r): lower e at every speed",
       "the force through the contact (unloading path) or the residual indentation of the surface"},
      {"static_friction", "static friction above kinetic", "mu_s - mu", "1", 0.1, 1.0, false,
       "stick holds up to (mu + excess) P: the impulse ratio at angles near the stick limit",
       "oblique impacts at angles near the stick limit (tan(angle) close to mu)"},
      {"tangential_compliance", "tangential contact compliance", "k/k_t", "1", 1.0, 10.0, false,
       "a tangential spring at the contact point: spin and v_C.x after small-angle impacts, T's "
       "tangential velocity can reverse",
       "the tangential velocity of the contact point through the contact, filmed at a higher rate",
       0.01},
      {"rolling_resistance", "rolling resistance (contact torque)", "rho", "m", 5e-4, 1e-2, false,
       "a contact torque: less spin after oblique impacts, v_C nearly unchanged",
       "spin after impacts with a known initial spin"},
      {"out_of_plane", "out-of-plane rotation (a measurement effect)", "tilt", "deg", 10.0, 60.0,
       true, "the projected marker distance shrinks by cos(tilt): apparent changes of the pose",
       "a second camera or a mirror view (stereo)"},
      {"out_of_plane_rate", "out-of-plane tilt growing through the impact (a measurement effect)",
       "dtilt/dt", "deg/s", 500.0, 1e4, true,
       "the marker distance dips toward the impact and recovers after it, and the markers on the "
       "face "
       "slide sideways: both velocities carry a bias of (thickness / 2) dtilt/dt along x_B",
       "a second camera or a mirror view (stereo), or markers at two depths", 0.0, true},
      {"out_of_plane_roll_rate",
       "out-of-plane roll growing through the impact (a measurement effect)", "droll/dt", "deg/s",
       500.0, 1e4, true,
       "the marker distance across the specimen dips toward the impact, and the markers on the "
       "face "
       "slide along y_B: both velocities carry a bias of (thickness / 2) droll/dt",
       "a second camera or a mirror view (stereo), or markers at two depths", 0.0, true},
  };
  return library;
}

bool AtUpperBound(const std::string& key, double value) {
  for (const auto& e : Library())
    if (e.key == key) return std::isfinite(value) && value >= e.upper * (1 - 1e-6);
  return false;
}

std::string UpperBoundNote(const std::string& key, double value) {
  return AtUpperBound(key, value) ? " (the library's upper bound)" : "";
}

namespace {

template <typename E, std::size_t N>
E FromString(const std::string& s, const std::array<E, N>& all, const char* what) {
  for (E e : all)
    if (s == ToString(e)) return e;
  throw std::invalid_argument(std::string("unknown ") + what + " '" + s + "'");
}

}  // namespace

const char* ToString(Identifiability v) {
  switch (v) {
    case Identifiability::kIdentified:
      return "identified";
    case Identifiability::kNotTested:
      return "not tested by these data";
    case Identifiability::kConfounded:
      return "confounded";
  }
  return "?";
}

const char* ToString(CandidateOutcome v) {
  switch (v) {
    case CandidateOutcome::kAdded:
      return "added";
    case CandidateOutcome::kIndistinguishable:
      return "indistinguishable from the added";
    case CandidateOutcome::kWeakerThanAdded:
      return "weaker than the added";
    case CandidateOutcome::kNotSignificant:
      return "not significant";
    case CandidateOutcome::kWorseHeldOut:
      return "no better on held-out trials";
    case CandidateOutcome::kBelowResolution:
      return "below the measurement's resolution";
    case CandidateOutcome::kNotTested:
      return "not tested by these data";
    case CandidateOutcome::kConfounded:
      return "confounded";
    case CandidateOutcome::kNotFitted:
      return "not fitted";
  }
  return "?";
}

const char* ToString(EffectForm v) { return v == EffectForm::kShared ? "shared" : "per surface"; }

const char* ToString(FindingStatus v) {
  switch (v) {
    case FindingStatus::kNamed:
      return "named";
    case FindingStatus::kTentative:
      return "tentative";
    case FindingStatus::kIndistinguishable:
      return "indistinguishable";
  }
  return "?";
}

Identifiability IdentifiabilityFromString(const std::string& s) {
  return FromString(s,
                    std::array{Identifiability::kIdentified, Identifiability::kNotTested,
                               Identifiability::kConfounded},
                    "identifiability");
}

CandidateOutcome CandidateOutcomeFromString(const std::string& s) {
  using O = CandidateOutcome;
  return FromString(s,
                    std::array{O::kAdded, O::kIndistinguishable, O::kWeakerThanAdded,
                               O::kNotSignificant, O::kWorseHeldOut, O::kBelowResolution,
                               O::kNotTested, O::kConfounded, O::kNotFitted},
                    "candidate outcome");
}

EffectForm EffectFormFromString(const std::string& s) {
  return FromString(s, std::array{EffectForm::kShared, EffectForm::kPerSurface}, "effect form");
}

FindingStatus FindingStatusFromString(const std::string& s) {
  return FromString(s,
                    std::array{FindingStatus::kNamed, FindingStatus::kTentative,
                               FindingStatus::kIndistinguishable},
                    "finding status");
}

void DiscoveryOptions::Validate() const {
  if (!(alpha > 0 && alpha < 0.5))
    throw std::invalid_argument("alpha must be in (0, 0.5), got " + Fmt(alpha));
  if (folds < 2) throw std::invalid_argument("folds must be >= 2, got " + std::to_string(folds));
  if (max_rounds < 1)
    throw std::invalid_argument("max_rounds must be >= 1, got " + std::to_string(max_rounds));
  if (jobs < 0) throw std::invalid_argument("jobs must be >= 0, got " + std::to_string(jobs));
  kinematics.Validate();
  if (!(relative_tolerance > 0 && relative_tolerance <= 1e-4))
    throw std::invalid_argument("relative_tolerance must be in (0, 1e-4], got " +
                                Fmt(relative_tolerance));
  if (!(measurement_floor >= 0 && measurement_floor < 0.1))
    throw std::invalid_argument("measurement_floor must be in [0, 0.1), got " +
                                Fmt(measurement_floor));
  if (!(replicate_tolerance >= 0 && replicate_tolerance < 0.1))
    throw std::invalid_argument("replicate_tolerance must be in [0, 0.1), got " +
                                Fmt(replicate_tolerance));
  if (!(marker_ratio_tolerance >= 0 && marker_ratio_tolerance < 0.1))
    throw std::invalid_argument("marker_ratio_tolerance must be in [0, 0.1), got " +
                                Fmt(marker_ratio_tolerance));
  for (const auto& k : candidates) internal::Entry(k);
}

}  // namespace hoof::discovery
