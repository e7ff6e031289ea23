// The discovery result as the terminal text (discovery/discovery_text.h), read without running
// the command: the facts each line must carry, not the sentences around them.
#include "discovery/discovery_text.h"

#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::discovery {
namespace {

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// The first line that starts (after its indent) with `head`, or "".
std::string LineStarting(const std::string& text, const std::string& head) {
  for (const auto& line : Lines(text))
    if (line.find_first_not_of(' ') != std::string::npos &&
        line.compare(line.find_first_not_of(' '), head.size(), head) == 0)
      return line;
  return "";
}

CandidateResult Candidate(const std::string& key, int rank, double p, CandidateOutcome outcome) {
  CandidateResult c;
  c.key = key;
  c.rank = rank;
  c.fitted = true;
  c.parameter = "c";
  c.unit = "N s/m^2";
  c.estimate = 7.35e7;
  c.se = 1.4e7;
  c.p_value = p;
  c.outcome = outcome;
  c.significant = p < 1e-3;
  c.reason = "the reason of " + key;
  return c;
}

DiscoveryResult OneRound() {
  DiscoveryResult r;
  r.success = true;
  r.trials_used = 144;
  r.trials_skipped = 2;
  r.verdict = "first line\n\nsecond line";
  Round round;
  round.accepted = "hunt_crossley";
  round.decision = "Added it";
  round.candidates.push_back(Candidate("hunt_crossley", 1, 0.0, CandidateOutcome::kAdded));
  round.candidates.push_back(
      Candidate("rolling_resistance", 2, 0.2, CandidateOutcome::kNotSignificant));
  CandidateResult unfitted;
  unfitted.key = "static_friction";
  unfitted.rank = 3;
  unfitted.message = "the simulator refused every start";
  round.candidates.push_back(unfitted);
  r.rounds.push_back(round);
  Finding f;
  f.key = "hunt_crossley";
  f.status = FindingStatus::kNamed;
  f.form = EffectForm::kPerSurface;
  f.parameter = "c";
  f.unit = "N s/m^2";
  f.surfaces = {"asphalt"};
  f.values = {{"hunt_crossley", "asphalt", 6.5e7, 1.1e7}};
  f.gap_shrink = 0.25;
  r.findings.push_back(f);
  return r;
}

TEST(DiscoveryTextTest, TheHeaderCountsTheTrialsAndTheVerdictIsIndented) {
  std::ostringstream os;
  WriteDiscoveryText(os, OneRound(), "S.h5");
  const auto lines = Lines(os.str());
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines[0].find("S.h5"), std::string::npos);
  EXPECT_NE(lines[0].find("144 trial(s) used, 2 skipped"), std::string::npos);
  EXPECT_NE(lines[0].find("1 round(s)"), std::string::npos);
  EXPECT_EQ(LineStarting(os.str(), "first line"), "  first line");
  EXPECT_EQ(LineStarting(os.str(), "second line"), "  second line");
}

TEST(DiscoveryTextTest, EachCandidateHasARowAndTheAddedOneIsStarred) {
  std::ostringstream os;
  WriteDiscoveryText(os, OneRound(), "S.h5");
  const std::string text = os.str();
  const std::string added = LineStarting(text, "1*");
  ASSERT_FALSE(added.empty()) << text;
  EXPECT_NE(added.find("hunt_crossley"), std::string::npos);
  // A p of 0 is below what a double holds, not a p of zero.
  EXPECT_NE(added.find("<1e-300"), std::string::npos);
  EXPECT_NE(added.find("c = 7.35e+07 +- 1.4e+07 N s/m^2"), std::string::npos);
  const std::string second = LineStarting(text, "2 ");
  EXPECT_NE(second.find("rolling_resistance"), std::string::npos);
  EXPECT_NE(second.find("0.2"), std::string::npos);
  EXPECT_TRUE(LineStarting(text, "2*").empty());
  const std::string unfitted = LineStarting(text, "3 ");
  EXPECT_NE(unfitted.find("not fitted: the simulator refused every start"), std::string::npos);
  // Why: the added candidate gets its reason; the one that is not significant does not.
  EXPECT_FALSE(LineStarting(text, "hunt_crossley (").empty());
  EXPECT_TRUE(LineStarting(text, "rolling_resistance (").empty());
}

TEST(DiscoveryTextTest, APerSurfaceFindingNamesItsSurfacesAndValues) {
  std::ostringstream os;
  WriteDiscoveryText(os, OneRound(), "S.h5");
  const std::string text = os.str();
  const auto at = text.find("Findings:");
  ASSERT_NE(at, std::string::npos);
  const std::string finding = LineStarting(text.substr(at), "named");
  EXPECT_NE(finding.find("hunt_crossley"), std::string::npos);
  EXPECT_NE(finding.find("found on asphalt"), std::string::npos);
  EXPECT_NE(finding.find("asphalt: c = 6.5e+07 +- 1.1e+07 N s/m^2"), std::string::npos);
}

TEST(DiscoveryTextTest, AResultThatCouldNotRunIsOneLineWithItsMessage) {
  DiscoveryResult r;
  r.trials_used = 1;
  r.trials_skipped = 3;
  r.message = "too few trials";
  std::ostringstream os;
  WriteDiscoveryText(os, r, "S.h5");
  const auto lines = Lines(os.str());
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_NE(lines[0].find("could not run"), std::string::npos);
  EXPECT_NE(lines[0].find("too few trials"), std::string::npos);
  EXPECT_NE(lines[0].find("1 trial(s) used, 3 skipped"), std::string::npos);
}

TEST(DiscoveryTextTest, NumbersThatAreNotFinitePrintAsADash) {
  EXPECT_EQ(Num(std::numeric_limits<double>::quiet_NaN()), "-");
  EXPECT_EQ(Num(std::numeric_limits<double>::infinity()), "-");
  EXPECT_EQ(Num(0.000123456, 3), "0.000123");
}

}  // namespace
}  // namespace hoof::discovery
