// One-way ANOVA against certified and independently computed values:
//  * the eleven NIST StRD one-way ANOVA sets (tests/data/nist/*.dat, certified values from
//    NIST's 500-digit computation, quoted in each file's header);
//  * an independent 50-digit evaluation of the textbook formulas (reference_anova.h);
//  * R's published output for the PlantGrowth data and exact rational sums of squares.
#include "stats/one_way_anova.h"

#include <cmath>
#include <cstdio>
#include <ostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nist_dat.h"
#include "reference_anova.h"
#include "stats/grouping.h"

namespace hoof::stats {
namespace {

using testing::ComputeReferenceAnova;
using testing::Lre;
using testing::ReadNistAnova;

/// NIST certified values (each file's header; https://www.itl.nist.gov/div898/strd/anova/).
struct Certified {
  const char* name;
  std::size_t df_between, df_within;
  double ss_between, ms_between, ss_within, ms_within, f, r_squared;
};

constexpr Certified kNist[] = {
    {"SiRstv", 4, 20, 5.11462616000000E-02, 1.27865654000000E-02, 2.16636560000000E-01,
     1.08318280000000E-02, 1.18046237440255E+00, 1.90999039051129E-01},
    {"SmLs01", 8, 180, 1.68000000000000E+00, 2.10000000000000E-01, 1.80000000000000E+00,
     1.00000000000000E-02, 2.10000000000000E+01, 4.82758620689655E-01},
    {"SmLs02", 8, 1800, 1.60800000000000E+01, 2.01000000000000E+00, 1.80000000000000E+01,
     1.00000000000000E-02, 2.01000000000000E+02, 4.71830985915493E-01},
    {"SmLs03", 8, 18000, 1.60080000000000E+02, 2.00100000000000E+01, 1.80000000000000E+02,
     1.00000000000000E-02, 2.00100000000000E+03, 4.70712773465067E-01},
    {"AtmWtAg", 1, 46, 3.63834187500000E-09, 3.63834187500000E-09, 1.04951729166667E-08,
     2.28155932971014E-10, 1.59467335677930E+01, 2.57426544538321E-01},
    {"SmLs04", 8, 180, 1.68000000000000E+00, 2.10000000000000E-01, 1.80000000000000E+00,
     1.00000000000000E-02, 2.10000000000000E+01, 4.82758620689655E-01},
    {"SmLs05", 8, 1800, 1.60800000000000E+01, 2.01000000000000E+00, 1.80000000000000E+01,
     1.00000000000000E-02, 2.01000000000000E+02, 4.71830985915493E-01},
    {"SmLs06", 8, 18000, 1.60080000000000E+02, 2.00100000000000E+01, 1.80000000000000E+02,
     1.00000000000000E-02, 2.00100000000000E+03, 4.70712773465067E-01},
    {"SmLs07", 8, 180, 1.68000000000000E+00, 2.10000000000000E-01, 1.80000000000000E+00,
     1.00000000000000E-02, 2.10000000000000E+01, 4.82758620689655E-01},
    {"SmLs08", 8, 1800, 1.60800000000000E+01, 2.01000000000000E+00, 1.80000000000000E+01,
     1.00000000000000E-02, 2.01000000000000E+02, 4.71830985915493E-01},
    {"SmLs09", 8, 18000, 1.60080000000000E+02, 2.00100000000000E+01, 1.80000000000000E+02,
     1.00000000000000E-02, 2.00100000000000E+03, 4.70712773465067E-01},
};

void ExpectRel(double actual, double expected, double rel, const std::string& what) {
  EXPECT_LE(std::fabs(actual - expected), rel * std::fabs(expected))
      << what << ": got " << actual << ", expected " << expected << " (LRE "
      << Lre(actual, expected) << ")";
}

// Names the data set in gtest's messages instead of dumping the struct's bytes.
void PrintTo(const Certified& c, std::ostream* os) { *os << c.name; }

class NistOneWayTest : public ::testing::TestWithParam<Certified> {};

// The certificates are for the decimal data. Scaled by 10^d (d = decimals in the file) the
// data are integers that double stores exactly, so nothing is lost on input; the ANOVA of
// y * 10^d has the same F and eta^2 and sums of squares 10^(2d) times larger. This is the
// modification StataCorp uses for its NIST certification (SmLs07-09 cannot be stored
// otherwise: 1000000000000.4 is held as 1000000000000.400024...). The 13 (SmLs07-09) or 7
// (SmLs04-06, AtmWtAg) constant leading digits, i.e. the stiffness, are unchanged.
TEST_P(NistOneWayTest, CertifiedValuesFromExactlyStoredData) {
  const Certified& c = GetParam();
  const auto file = ReadNistAnova(c.name);
  const OneWayAnovaResult r = OneWayAnova(GroupByLabel(file.scaled, file.labels));
  const double s2 = std::pow(10.0, 2 * file.decimals);  // exact: 10^14 at most
  EXPECT_EQ(r.df_between, c.df_between);
  EXPECT_EQ(r.df_within, c.df_within);
  EXPECT_EQ(r.df_total, c.df_between + c.df_within);
  const double rel = 1e-10;  // the brief: at least 10 significant digits
  ExpectRel(r.ss_between, c.ss_between * s2, rel, "SS between");
  ExpectRel(r.ms_between, c.ms_between * s2, rel, "MS between");
  ExpectRel(r.ss_within, c.ss_within * s2, rel, "SS within");
  ExpectRel(r.ms_within, c.ms_within * s2, rel, "MS within");
  ExpectRel(r.f, c.f, rel, "F");
  ExpectRel(r.eta_squared, c.r_squared, rel, "eta^2 (certified R^2)");
  std::printf("[ LRE ] %-8s exact input: F %.1f, SSb %.1f, SSw %.1f, MSb %.1f, MSw %.1f\n", c.name,
              Lre(r.f, c.f), Lre(r.ss_between, c.ss_between * s2),
              Lre(r.ss_within, c.ss_within * s2), Lre(r.ms_between, c.ms_between * s2),
              Lre(r.ms_within, c.ms_within * s2));
}

// The data as a program reads them: the nearest doubles. Their exact ANOVA (50 digits) is the
// best any double-input algorithm can do, and the library must reproduce it to 13 digits.
// How far that exact answer is from the certificate is a property of the input, not of the
// algorithm: rational arithmetic on the doubles gives relative gaps of about 1e-15 (SiRstv,
// SmLs01-03), 7e-11 (AtmWtAg), 4e-11 to 1.2e-10 (SmLs04-06) and 4e-5 to 1.2e-4 (SmLs07-09).
TEST_P(NistOneWayTest, DoubleInputMatchesFiftyDigitReference) {
  const Certified& c = GetParam();
  const auto file = ReadNistAnova(c.name);
  const OneWayAnovaResult r = OneWayAnova(GroupByLabel(file.values, file.labels));
  const auto ref = ComputeReferenceAnova(file.values, file.labels);
  const double rel = 1e-13;
  ExpectRel(r.ss_between, static_cast<double>(ref.ss_between), rel, "SS between");
  ExpectRel(r.ss_within, static_cast<double>(ref.ss_within), rel, "SS within");
  ExpectRel(r.ms_between, static_cast<double>(ref.ms_between), rel, "MS between");
  ExpectRel(r.ms_within, static_cast<double>(ref.ms_within), rel, "MS within");
  ExpectRel(r.f, static_cast<double>(ref.f), rel, "F");
  ExpectRel(r.eta_squared, static_cast<double>(ref.eta_squared), rel, "eta^2");
  std::printf(
      "[ LRE ] %-8s double input vs certified: F %.1f, SSb %.1f, SSw %.1f; "
      "vs 50-digit reference: F %.1f, SSb %.1f, SSw %.1f\n",
      c.name, Lre(r.f, c.f), Lre(r.ss_between, c.ss_between), Lre(r.ss_within, c.ss_within),
      Lre(r.f, static_cast<double>(ref.f)), Lre(r.ss_between, static_cast<double>(ref.ss_between)),
      Lre(r.ss_within, static_cast<double>(ref.ss_within)));
}

INSTANTIATE_TEST_SUITE_P(AllSets, NistOneWayTest, ::testing::ValuesIn(kNist),
                         [](const ::testing::TestParamInfo<Certified>& param_info) {
                           return std::string(param_info.param.name);
                         });

// SiRstv as read (3 constant leading digits: the doubles are close enough) against the
// certificate, and the p-value against R 4.2 (anova(lm(resistance ~ factor(instrument))),
// quoted in the .dat header as 0.34945).
TEST(OneWayAnovaTest, SiRstvAsReadMatchesCertificateAndR) {
  const auto file = ReadNistAnova("SiRstv");
  const OneWayAnovaResult r = OneWayAnova(GroupByLabel(file.values, file.labels));
  const Certified& c = kNist[0];
  ExpectRel(r.f, c.f, 1e-10, "F");
  ExpectRel(r.ss_between, c.ss_between, 1e-10, "SS between");
  ExpectRel(r.ss_within, c.ss_within, 1e-10, "SS within");
  ExpectRel(r.ms_between, c.ms_between, 1e-10, "MS between");
  ExpectRel(r.ms_within, c.ms_within, 1e-10, "MS within");
  ExpectRel(r.residual_sd, 1.04076068334656E-01, 1e-10, "residual SD");
  EXPECT_NEAR(r.p, 0.34945, 0.5e-5);  // printed to 5 decimals
  EXPECT_EQ(r.groups, 5u);
  EXPECT_EQ(r.observations, 25u);
}

// PlantGrowth (Dobson 1983; R's datasets::PlantGrowth). Exact sums of squares from the decimal
// data in rational arithmetic (Python fractions): SS_between = 3.76634, SS_within = 10.49209.
// R: summary(aov(weight ~ group, PlantGrowth)) prints F = 4.846, p = 0.0159, and
// oneway.test(..., var.equal = TRUE) prints F = 4.8461, p-value = 0.01591.
TEST(OneWayAnovaTest, PlantGrowthMatchesExactSumsAndR) {
  const auto data = MakeGroups({"ctrl", "trt1", "trt2"},
                               {{4.17, 5.58, 5.18, 6.11, 4.50, 4.61, 5.17, 4.53, 5.33, 5.14},
                                {4.81, 4.17, 4.41, 3.59, 5.87, 3.83, 6.03, 4.89, 4.32, 4.69},
                                {6.31, 5.12, 5.54, 5.50, 5.37, 5.29, 4.92, 6.15, 5.80, 5.26}});
  const OneWayAnovaResult r = OneWayAnova(data);
  ExpectRel(r.ss_between, 3.76634, 1e-12, "SS between");
  ExpectRel(r.ss_within, 10.49209, 1e-12, "SS within");
  ExpectRel(r.ss_total, 3.76634 + 10.49209, 1e-12, "SS total");
  ExpectRel(r.eta_squared, 3.76634 / (3.76634 + 10.49209), 1e-12, "eta^2");
  EXPECT_NEAR(r.f, 4.8461, 0.5e-4);
  EXPECT_NEAR(r.p, 0.01591, 0.5e-5);
  EXPECT_EQ(r.df_between, 2u);
  EXPECT_EQ(r.df_within, 27u);
}

// Unbalanced groups (3 to 250 values) with 13 constant leading digits, seeded: the NIST sets
// are all balanced, the library must not depend on that. Truth: the 50-digit reference.
TEST(OneWayAnovaTest, UnbalancedStiffDataMatchFiftyDigitReference) {
  std::mt19937_64 rng(20240521);
  std::normal_distribution<double> noise(0.0, 0.1);
  const std::vector<std::size_t> sizes = {3, 17, 250, 41, 2};
  const std::vector<double> effects = {0.0, 0.05, -0.02, 0.11, 0.3};
  std::vector<double> y;
  std::vector<std::string> labels;
  for (std::size_t g = 0; g < sizes.size(); ++g)
    for (std::size_t i = 0; i < sizes[g]; ++i) {
      y.push_back(1e12 + effects[g] + noise(rng));
      labels.push_back(std::string("g").append(std::to_string(g)));
    }
  const OneWayAnovaResult r = OneWayAnova(GroupByLabel(y, labels));
  const auto ref = ComputeReferenceAnova(y, labels);
  ExpectRel(r.ss_between, static_cast<double>(ref.ss_between), 1e-13, "SS between");
  ExpectRel(r.ss_within, static_cast<double>(ref.ss_within), 1e-13, "SS within");
  ExpectRel(r.f, static_cast<double>(ref.f), 1e-13, "F");
  EXPECT_EQ(r.df_within, 313u - 5u);
}

// Bad input: each case is a std::invalid_argument whose message names the problem.
void ExpectInvalid(const GroupedData& data, const std::string& needle) {
  try {
    OneWayAnova(data);
    ADD_FAILURE() << "expected std::invalid_argument mentioning " << needle;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(OneWayAnovaTest, BadInputIsRejectedWithAClearMessage) {
  ExpectInvalid(MakeGroups({"only"}, {{1.0, 2.0, 3.0}}), "at least 2 groups");
  ExpectInvalid(MakeGroups({"only"}, {{1.0, 2.0, 3.0}}), "\"only\"");
  ExpectInvalid(MakeGroups({"a", "lonely"}, {{1.0, 2.0}, {3.0}}), "group \"lonely\" has 1");
  ExpectInvalid(MakeGroups({"a", "b"}, {{2.5, 2.5}, {2.5, 2.5, 2.5}}), "all 5 observations");
  ExpectInvalid(MakeGroups({"a", "b"}, {{1.0, 1.0}, {2.0, 2.0}}), "every group is constant");
}

TEST(OneWayAnovaTest, NonFiniteValuesAreRejectedNamingTheGroup) {
  const double nan = std::nan("");
  const double inf = INFINITY;
  try {
    GroupByLabel({1.0, 2.0, nan, 4.0}, {"a", "a", "b", "b"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("observation 2 (group \"b\") is NaN"), std::string::npos)
        << e.what();
  }
  try {
    GroupByLabel({1.0, -inf}, {"a", "c"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("group \"c\") is infinite"), std::string::npos)
        << e.what();
  }
}

// A constant response in one group only is valid data: the ANOVA is defined.
TEST(OneWayAnovaTest, OneConstantGroupIsFine) {
  const OneWayAnovaResult r = OneWayAnova(MakeGroups({"a", "b"}, {{1.0, 1.0}, {2.0, 4.0}}));
  // Means 1 and 3, grand mean 2: SS_between = 2*1 + 2*1 = 4; SS_within = 0 + 2 = 2.
  EXPECT_DOUBLE_EQ(r.ss_between, 4.0);
  EXPECT_DOUBLE_EQ(r.ss_within, 2.0);
  EXPECT_DOUBLE_EQ(r.f, 4.0);
  // F(1, 2) upper tail = 1 - sqrt(F / (2 + F)) (t with 2 df, t^2 = F): 1 - sqrt(2/3).
  EXPECT_NEAR(r.p, 1.0 - std::sqrt(2.0 / 3.0), 1e-14);
}

}  // namespace
}  // namespace hoof::stats
