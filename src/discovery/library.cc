// The candidate library, the names of the workflow's enums, and option checks
// (docs/discovery.md).
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/frames.h"
#include "discovery/internal.h"
#include "format/number_format.h"

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
  c.detection_limit = core::kNaN;
  return c;
}

void Apply(const std::string& key, double value, dynamics::ContactExtensions& x) {
  const auto* field = dynamics::FindContactExtension(Entry(key).extension);
  if (!field) throw std::invalid_argument("no contact extension for '" + key + "'");
  x.*field->member = value;
}

std::string Fmt(double v, int precision) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

std::string JoinedWords(const std::vector<std::string>& words) {
  std::string s;
  for (std::size_t i = 0; i < words.size(); ++i)
    s += (i == 0 ? "" : i + 1 == words.size() ? " and " : ", ") + words[i];
  return s;
}

std::string UnitSuffix(const std::string& unit) {
  return unit == "1" || unit.empty() ? "" : " " + unit;
}

std::string FmtP(double p) { return format::PAgainstSmallLevel(p); }

}  // namespace internal

bool JudgedOnDensity(const CandidateResult& c) {
  return std::isfinite(c.cv_density) && std::isfinite(c.cv_density_current);
}

bool HeldOutFell(const CandidateResult& c) {
  return JudgedOnDensity(c) ? c.cv_density < c.cv_density_current : c.cv_error < c.cv_error_current;
}

bool ContactEvidenceHolds(const CandidateResult& c, double naming_level, bool later_round) {
  return c.fitted && c.p_value < naming_level && c.wald_clear && HeldOutFell(c) &&
         (!later_round || c.cv_p < kLaterRoundHeldOutLevel) &&
         !(c.p_without_influential >= kWithoutInfluentialLevel);
}

std::array<std::string, 2> HeldOutScores(const CandidateResult& c) {
  if (!JudgedOnDensity(c)) return {internal::Fmt(c.cv_error), internal::Fmt(c.cv_error_current)};
  auto fixed = [](double v) {
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(3);
    s << v;
    return s.str();
  };
  return {fixed(c.cv_density), fixed(c.cv_density_current)};
}

std::string HeldOutText(const CandidateResult& c) {
  const auto [now, current] = HeldOutScores(c);
  return (JudgedOnDensity(c) ? "held-out -log density " : "held-out error ") + current + " -> " +
         now + " (" + (JudgedOnDensity(c) ? kHeldOutDensityUnit : kHeldOutErrorUnit) + ")";
}

std::string GapChangeText(double gap_shrink) {
  if (!std::isfinite(gap_shrink)) return "n/a";
  if (std::abs(100 * gap_shrink) < 0.05) return "unchanged";
  std::ostringstream s;
  s.precision(3);
  s << std::abs(100 * gap_shrink) << (gap_shrink > 0 ? " % smaller" : " % larger");
  return s.str();
}

using internal::Fmt;

// One declaration per effect, as data: the whole table is one function, long by design, so that
// an effect's key, words, sizes and extension stand together (a new effect is a new entry here
// and a field of dynamics::ContactExtensionFields() in dynamics/parameters.h).
const std::vector<LibraryEntry>& Library() {
  static const std::vector<LibraryEntry> library = {
      {.key = "hunt_crossley",
       .name = "velocity-dependent (Hunt-Crossley) damping",
       .parameter = "c",
       .unit = "N s/m^2",
       .probe = 2e7,
       .upper = 5e8,
       .signature = "extra damping c |delta| delta' in compression: e falls as the impact speed "
                    "rises",
       .separating_measurement = "impacts over a wider range of speeds, or the force through the "
                                 "contact (its hysteresis loop grows with speed)",
       .extension = "hunt_crossley_N_s_m2"},
      {.key = "hertz_stiffness",
       .name = "nonlinear (Hertzian) stiffness",
       .parameter = "p",
       .unit = "1",
       .probe = 0.5,
       .upper = 1.0,
       .signature = "elastic force k |delta| (|delta| / delta_ref)^p: the effective damping ratio "
                    "changes with speed, e rises with speed",
       .separating_measurement = "the contact duration against impact speed (it shortens with "
                                 "speed only for a stiffening contact), or the force through the "
                                 "contact",
       .extension = "stiffness_exponent_extra"},
      {.key = "plastic_unloading",
       .name = "dissipative (plastic) restitution",
       .parameter = "r",
       .unit = "1",
       .probe = 0.5,
       .upper = 10.0,
       .signature = "unloading stiffer than loading, k (1 + r): lower e at every speed",
       .separating_measurement = "the force through the contact (unloading path) or the residual "
                                 "indentation of the surface",
       .extension = "unloading_stiffness_ratio"},
      {.key = "static_friction",
       .name = "static friction above kinetic",
       .parameter = "mu_s - mu",
       .unit = "1",
       .probe = 0.1,
       .upper = 1.0,
       .signature = "stick holds up to (mu + excess) P: the impulse ratio at angles near the "
                    "stick limit",
       .separating_measurement = "oblique impacts at angles near the stick limit (tan(angle) "
                                 "close to mu)",
       .extension = "static_friction_excess"},
      {.key = "tangential_compliance",
       .name = "tangential contact compliance",
       .parameter = "k/k_t",
       .unit = "1",
       .probe = 1.0,
       .upper = 10.0,
       .signature = "a tangential spring at the contact point: spin and v_C.x after small-angle "
                    "impacts, T's tangential velocity can reverse",
       .separating_measurement = "the tangential velocity of the contact point through the "
                                 "contact, filmed at a higher rate",
       .smallest = 0.01,
       // The spring's oscillation through the stick phase ends at separation at a phase that
       // turns with sqrt(k_t / k): the spin after a small-angle impact swings in sign between
       // sizes 1.3 times apart near 0.01, so the ladder needs about 8 sizes per such swing.
       .ladder_per_decade = 80.0,
       .friction_limited = true,
       .starts_without_gain = 3,
       .profile_sizes = 28,
       .extension = "tangential_compliance_ratio"},
      {.key = "rolling_resistance",
       .name = "rolling resistance (contact torque)",
       .parameter = "rho",
       .unit = "m",
       .probe = 5e-4,
       .upper = 1e-2,
       .signature = "a contact torque: less spin after oblique impacts, v_C nearly unchanged",
       .separating_measurement = "spin after impacts with a known initial spin",
       .extension = "rolling_resistance_m"},
      {.key = "out_of_plane",
       .name = "out-of-plane rotation (a measurement effect)",
       .parameter = "tilt",
       .unit = "deg",
       .probe = 10.0,
       .upper = 60.0,
       .measurement_effect = true,
       .signature = "the projected marker distance shrinks by cos(tilt): apparent changes of the "
                    "pose",
       .separating_measurement = "a second camera or a mirror view (stereo)",
       .extension = ""},
      {.key = "out_of_plane_rate",
       .name = "out-of-plane tilt growing through the impact (a measurement effect)",
       .parameter = "dtilt/dt",
       .unit = "deg/s",
       .probe = 500.0,
       .upper = 1e4,
       .measurement_effect = true,
       .signature = "the marker distance dips toward the impact and recovers after it, and the "
                    "markers on the face slide sideways: both velocities carry a bias of "
                    "(thickness / 2) dtilt/dt along x_B",
       .separating_measurement = "a second camera or a mirror view (stereo), or markers at two "
                                 "depths",
       .rotation_rate = true,
       .extension = ""},
      {.key = "out_of_plane_roll_rate",
       .name = "out-of-plane roll growing through the impact (a measurement effect)",
       .parameter = "droll/dt",
       .unit = "deg/s",
       .probe = 500.0,
       .upper = 1e4,
       .measurement_effect = true,
       .signature = "the marker distance across the specimen dips toward the impact, and the "
                    "markers on the face slide along y_B: both velocities carry a bias of "
                    "(thickness / 2) droll/dt",
       .separating_measurement = "a second camera or a mirror view (stereo), or markers at two "
                                 "depths",
       .rotation_rate = true,
       .extension = ""},
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

const std::array<CandidateOutcome, 11>& AllCandidateOutcomes() {
  using O = CandidateOutcome;
  static const std::array<CandidateOutcome, 11> all{
      O::kAdded,        O::kIndistinguishable, O::kWeakerThanAdded, O::kNotSignificant,
      O::kWorseHeldOut, O::kBelowResolution,   O::kAtSmallestValue, O::kRestsOnOneTrial,
      O::kNotTested,    O::kConfounded,        O::kNotFitted};
  return all;
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
    case CandidateOutcome::kAtSmallestValue:
      return "on the library's smallest value";
    case CandidateOutcome::kRestsOnOneTrial:
      return "rests on one trial";
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
  return FromString(s, AllCandidateOutcomes(), "candidate outcome");
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
