// The rule that names a contact candidate (ContactEvidenceHolds, src/discovery/library.cc), on
// candidates whose evidence differs in one respect at a time: each condition of the rule
// (docs/discovery.md, "Candidates and the decision" and "The held-out rule") must be able to
// refuse a candidate on its own, and the held-out significance only in a round after an
// effect was added.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "discovery/discovery.h"
#include "discovery/internal.h"

namespace hoof::discovery {
namespace {

constexpr double kLevel = 1e-3;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A contact candidate that every condition names: p far below the level, clear of 0, its
/// held-out density lower by 0.5 nats per trial and significantly so; its influence not checked
/// (p_without_influential NaN).
CandidateResult Strong() {
  CandidateResult c;
  c.key = "hunt_crossley";
  c.fitted = true;
  c.p_value = 1e-8;
  c.wald_clear = true;
  c.cv_error = 1.2;
  c.cv_error_current = 1.1;  // its error in the current model's units rose: not what counts
  c.cv_density = -10.5;
  c.cv_density_current = -10.0;
  c.cv_p = 0.001;
  return c;
}

TEST(DecisionRuleTest, AStrongCandidateIsNamedInAnyRound) {
  EXPECT_TRUE(ContactEvidenceHolds(Strong(), kLevel, false));
  EXPECT_TRUE(ContactEvidenceHolds(Strong(), kLevel, true));
}

TEST(DecisionRuleTest, EachConditionRefusesOnItsOwn) {
  CandidateResult c = Strong();
  c.fitted = false;
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, false)) << "a failed fit";
  c = Strong();
  c.p_value = kLevel;  // not below
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, false)) << "p at the naming level";
  c.p_value = kNaN;
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, false)) << "no p";
  c = Strong();
  c.wald_clear = false;
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, false)) << "an estimate not clear of 0";
  c = Strong();
  c.cv_density = c.cv_density_current + 0.01;
  c.cv_error = 0.5;  // a lower error does not stand in for the density
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, false)) << "a higher held-out density";
  c = Strong();
  c.p_without_influential = kWithoutInfluentialLevel;  // not below
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, false)) << "resting on one trial";
  // A confirmation of the chosen candidate: at the family-wise alpha, not the naming level.
  c.p_without_influential = 0.5 * kWithoutInfluentialLevel;
  ASSERT_GT(c.p_without_influential, kLevel);
  EXPECT_TRUE(ContactEvidenceHolds(c, kLevel, false)) << "holding without its most influential";
}

TEST(DecisionRuleTest, AfterAnAddedEffectTheHeldOutDensityMustFallSignificantly) {
  CandidateResult c = Strong();
  c.cv_p = 0.2;  // lower, but not significantly
  EXPECT_TRUE(ContactEvidenceHolds(c, kLevel, false)) << "round 1 asks only that it fell";
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, true));
  c.cv_p = kLaterRoundHeldOutLevel;  // not below
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, true));
  c.cv_p = 0.049;
  EXPECT_TRUE(ContactEvidenceHolds(c, kLevel, true));
}

TEST(DecisionRuleTest, WithoutADensityTheHeldOutErrorDecides) {
  // An out-of-plane candidate is judged on the image: no density, its held-out error.
  CandidateResult c = Strong();
  c.cv_density = kNaN;
  c.cv_density_current = kNaN;
  EXPECT_FALSE(JudgedOnDensity(c));
  EXPECT_FALSE(ContactEvidenceHolds(c, kLevel, false)) << "its error rose";
  c.cv_error = 1.0;
  EXPECT_TRUE(ContactEvidenceHolds(c, kLevel, false));
}

}  // namespace
}  // namespace hoof::discovery

namespace hoof::discovery::internal {
namespace {

// A later round does not call "not tested by these data" what an earlier round found
// significant (KeepEarlierEvidence, src/discovery/discovery.cc): a scorecard study had
// Hunt-Crossley damping at p = 1.6e-8 in round 1, and "not tested" in round 2 once another
// effect was in the model, both printed in one verdict.
TEST(KeepEarlierEvidenceTest, ALaterRoundKeepsAnEarlierSignificanceInView) {
  Round first;
  first.index = 1;
  first.naming_level = 7.5e-4;
  CandidateResult strong = Strong();
  strong.p_value = 1.6e-8;
  strong.outcome = CandidateOutcome::kWeakerThanAdded;
  CandidateResult weak = Strong();
  weak.key = "static_friction";
  weak.p_value = 0.2;
  weak.outcome = CandidateOutcome::kNotSignificant;
  first.candidates = {strong, weak};

  Round second;
  second.index = 2;
  second.naming_level = 6.5e-4;
  for (const char* key : {"hunt_crossley", "static_friction", "plastic_unloading"}) {
    CandidateResult c;
    c.key = key;
    c.p_value = 1.0;
    c.lr_statistic = 0.0;
    c.identifiability = Identifiability::kNotTested;
    c.outcome = CandidateOutcome::kNotTested;
    c.reason = "no trial is sensitive to it";
    second.candidates.push_back(c);
  }
  KeepEarlierEvidence({first}, {"tangential_compliance"}, second);

  const CandidateResult& hc = second.candidates[0];
  EXPECT_EQ(hc.outcome, CandidateOutcome::kNotSignificant);
  EXPECT_EQ(hc.identifiability, Identifiability::kIdentified);
  EXPECT_NE(hc.reason.find(FmtP(1.6e-8)), std::string::npos) << hc.reason;
  EXPECT_NE(hc.reason.find("tangential contact compliance"), std::string::npos) << hc.reason;
  // Not significant before (p = 0.2), or never tried: "not tested" stands.
  for (std::size_t i : {1u, 2u}) {
    EXPECT_EQ(second.candidates[i].outcome, CandidateOutcome::kNotTested);
    EXPECT_EQ(second.candidates[i].reason, "no trial is sensitive to it");
  }
}

// The verdict says what became of a candidate that was significant in an earlier round, even
// where its p in the later round is 1; a candidate never significant is not listed.
TEST(KeepEarlierEvidenceTest, TheVerdictListsWhatBecameOfAnEarlierSignificance) {
  DiscoveryResult out;
  out.success = true;
  Round first;
  first.index = 1;
  first.naming_level = 7.5e-4;
  first.accepted = "tangential_compliance";
  CandidateResult strong = Strong();
  strong.name = "velocity-dependent (Hunt-Crossley) damping";
  strong.p_value = 1.6e-8;
  strong.outcome = CandidateOutcome::kWeakerThanAdded;
  strong.reason = "the earlier reason";
  CandidateResult never = Strong();
  never.key = "hertz_stiffness";
  never.name = "nonlinear (Hertzian) stiffness";
  never.p_value = 1.0;
  never.outcome = CandidateOutcome::kNotSignificant;
  first.candidates = {strong, never};
  Round second = first;
  second.index = 2;
  second.accepted.clear();
  for (auto& c : second.candidates) {
    c.p_value = 1.0;
    c.outcome = CandidateOutcome::kNotSignificant;
    c.reason = c.key == "hunt_crossley" ? "the later reason" : "never significant";
  }
  out.rounds = {first, second};
  const std::string v = VerdictText(out, DiscoveryOptions{}, 0);
  EXPECT_NE(v.find("Round 1, velocity-dependent (Hunt-Crossley) damping (p = 1.60e-08): not "
                   "added, the earlier reason."),
            std::string::npos)
      << v;
  EXPECT_NE(v.find("Round 2, velocity-dependent (Hunt-Crossley) damping (p = 1): not added, the "
                   "later reason."),
            std::string::npos)
      << v;
  EXPECT_EQ(v.find("never significant"), std::string::npos) << v;
}

}  // namespace
}  // namespace hoof::discovery::internal
