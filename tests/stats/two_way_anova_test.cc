// Two-way ANOVA against exact sums of squares (balanced: R's ToothGrowth; unbalanced: a 2 x 2
// design worked by hand) and R's published table.
#include "stats/two_way_anova.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::stats {
namespace {

struct Data {
  std::vector<double> y;
  std::vector<std::string> a, b;
};

// R's datasets::ToothGrowth (Crampton 1947): len by supp (VC, OJ) x dose (0.5, 1, 2),
// 10 guinea pigs per cell.
Data ToothGrowth() {
  const std::vector<std::pair<std::string, std::vector<std::vector<double>>>> supp = {
      {"VC",
       {{4.2, 11.5, 7.3, 5.8, 6.4, 10.0, 11.2, 11.2, 5.2, 7.0},
        {16.5, 16.5, 15.2, 17.3, 22.5, 17.3, 13.6, 14.5, 18.8, 15.5},
        {23.6, 18.5, 33.9, 25.5, 26.4, 32.5, 26.7, 21.5, 23.3, 29.5}}},
      {"OJ",
       {{15.2, 21.5, 17.6, 9.7, 14.5, 10.0, 8.2, 9.4, 16.5, 9.7},
        {19.7, 23.3, 23.6, 26.4, 20.0, 25.2, 25.8, 21.2, 14.5, 27.3},
        {25.5, 26.4, 22.4, 24.5, 24.8, 30.9, 26.4, 27.3, 29.4, 23.0}}}};
  const std::vector<std::string> dose = {"0.5", "1", "2"};
  Data d;
  for (const auto& [s, cells] : supp)
    for (std::size_t j = 0; j < 3; ++j)
      for (double v : cells[j]) {
        d.y.push_back(v);
        d.a.push_back(s);
        d.b.push_back(dose[j]);
      }
  return d;
}

void ExpectRel(double actual, double expected, double rel, const std::string& what) {
  EXPECT_LE(std::fabs(actual - expected), rel * std::fabs(expected))
      << what << ": got " << actual << ", expected " << expected;
}

// Exact sums of squares of ToothGrowth from the decimal data in rational arithmetic (Python
// fractions): supp 4107/20, dose 7279303/3000, supp:dose 108319/1000, error 356053/500,
// total 2589157/750. R: summary(aov(len ~ supp * factor(dose), ToothGrowth)) prints
//   supp 1 205.4 205.4 15.572 0.000231 / dose 2 2426.4 1213.2 92.000 < 2e-16 /
//   supp:dose 2 108.3 54.2 4.107 0.021860 / Residuals 54 712.1 13.2.
// The design is balanced, so Type I and Type III must both give this table.
TEST(TwoWayAnovaTest, ToothGrowthMatchesExactSumsAndR) {
  const Data d = ToothGrowth();
  for (SumOfSquaresType type : {SumOfSquaresType::kTypeIII, SumOfSquaresType::kTypeI}) {
    TwoWayOptions o;
    o.type = type;
    o.name_a = "supp";
    o.name_b = "dose";
    const TwoWayAnovaResult r = TwoWayAnova(d.y, d.a, d.b, o);
    SCOPED_TRACE(ToString(type));
    EXPECT_TRUE(r.balanced);
    EXPECT_EQ(r.levels_a, (std::vector<std::string>{"VC", "OJ"}));
    EXPECT_EQ(r.a.source, "supp");
    EXPECT_EQ(r.ab.source, "supp:dose");
    EXPECT_EQ(r.a.df, 1u);
    EXPECT_EQ(r.b.df, 2u);
    EXPECT_EQ(r.ab.df, 2u);
    EXPECT_EQ(r.error.df, 54u);
    EXPECT_EQ(r.df_total, 59u);
    ExpectRel(r.a.ss, 4107.0 / 20, 1e-12, "SS supp");
    ExpectRel(r.b.ss, 7279303.0 / 3000, 1e-12, "SS dose");
    ExpectRel(r.ab.ss, 108319.0 / 1000, 1e-12, "SS supp:dose");
    ExpectRel(r.error.ss, 356053.0 / 500, 1e-12, "SS error");
    ExpectRel(r.ss_total, 2589157.0 / 750, 1e-12, "SS total");
    EXPECT_NEAR(r.a.f, 15.572, 0.5e-3);
    EXPECT_NEAR(r.b.f, 92.000, 0.5e-3);
    EXPECT_NEAR(r.ab.f, 4.107, 0.5e-3);
    EXPECT_NEAR(r.a.p, 0.000231, 0.5e-6);
    EXPECT_LT(r.b.p, 2e-16);
    EXPECT_NEAR(r.ab.p, 0.021860, 0.5e-6);
    EXPECT_TRUE(std::isnan(r.error.f));
  }
}

// The same data as 10 len + 10^12: integers, stored exactly, with 12 constant leading
// digits. Sums of squares scale by 100, F and p do not change.
TEST(TwoWayAnovaTest, StiffToothGrowthKeepsItsDigits) {
  Data d = ToothGrowth();
  for (double& v : d.y) v = std::round(10.0 * v) + 1e12;
  const TwoWayAnovaResult r = TwoWayAnova(d.y, d.a, d.b);
  ExpectRel(r.a.ss, 100 * 4107.0 / 20, 1e-12, "SS supp");
  ExpectRel(r.b.ss, 100 * 7279303.0 / 3000, 1e-12, "SS dose");
  ExpectRel(r.ab.ss, 100 * 108319.0 / 1000, 1e-12, "SS supp:dose");
  ExpectRel(r.error.ss, 100 * 356053.0 / 500, 1e-12, "SS error");
}

// Unbalanced 2 x 2, worked by hand. Cells (A, B): (1,1) {3, 5} mean 4; (1,2) {6, 8, 10} mean 8;
// (2,1) {1} mean 1; (2,2) {3, 5, 7, 9} mean 6. SS_error = 2 + 8 + 0 + 20 = 30, df 6.
// Type III in a 2 x 2 design: each effect is one contrast c of the cell means, and
// SS = (c'm)^2 / sum(c_ij^2 / n_ij) with c = +-1, i.e. (c'm)^2 / (1/2 + 1/3 + 1 + 1/4), 12/25 x:
//   A: (4 + 8 - 1 - 6)^2 = 25 -> 12;  B: (4 - 8 + 1 - 6)^2 = 81 -> 38.88;
//   AB: (4 - 8 - 1 + 6)^2 = 1 -> 0.48.
// Type I (A first): grand mean 5.7, row means 6.4 and 5 (n = 5 each): SS_A = 10 * 0.49 = 4.9;
// SS_AB|A,B = the Type III AB = 0.48; the cell-means SS is 2 * 1.7^2 + 3 * 2.3^2 + 4.7^2 +
// 4 * 0.3^2 = 44.1, so SS_B|A = 44.1 - 4.9 - 0.48 = 38.72. Total = 44.1 + 30 = 74.1.
Data Unbalanced() {
  Data d;
  const auto add = [&d](const char* a, const char* b, std::vector<double> v) {
    for (double x : v) {
      d.y.push_back(x);
      d.a.push_back(a);
      d.b.push_back(b);
    }
  };
  add("a1", "b1", {3, 5});
  add("a2", "b2", {3, 5});
  add("a1", "b2", {6, 8, 10});
  add("a2", "b1", {1});
  add("a2", "b2", {7, 9});
  return d;
}

TEST(TwoWayAnovaTest, UnbalancedTypeIIIMatchesTheContrastFormula) {
  const Data d = Unbalanced();
  const TwoWayAnovaResult r = TwoWayAnova(d.y, d.a, d.b);
  EXPECT_FALSE(r.balanced);
  EXPECT_EQ(r.cell_counts, (std::vector<std::vector<std::size_t>>{{2, 3}, {1, 4}}));
  ExpectRel(r.a.ss, 12.0, 1e-13, "A");
  ExpectRel(r.b.ss, 38.88, 1e-13, "B");
  ExpectRel(r.ab.ss, 0.48, 1e-13, "AB");
  ExpectRel(r.error.ss, 30.0, 1e-13, "error");
  EXPECT_EQ(r.error.df, 6u);
  ExpectRel(r.a.f, 12.0 / 5.0, 1e-13, "F A");
  ExpectRel(r.ss_total, 74.1, 1e-13, "total");
  // p of F(1, 6) at F = 2.4 is the two-sided t(6) p at t = sqrt 2.4; for even df,
  // Abramowitz & Stegun 26.7.3: with theta = atan(t / sqrt 6),
  // p = 1 - sin(theta) (1 + cos^2(theta) / 2 + 3 cos^4(theta) / 8).
  const double theta = std::atan(std::sqrt(2.4 / 6.0));
  const double c2 = std::cos(theta) * std::cos(theta);
  EXPECT_NEAR(r.a.p, 1.0 - std::sin(theta) * (1.0 + c2 / 2.0 + 3.0 * c2 * c2 / 8.0), 1e-13);

  // Type III does not depend on which factor is called A.
  const TwoWayAnovaResult swapped = TwoWayAnova(d.y, d.b, d.a);
  ExpectRel(swapped.a.ss, 38.88, 1e-13, "swapped A (was B)");
  ExpectRel(swapped.b.ss, 12.0, 1e-13, "swapped B (was A)");
  ExpectRel(swapped.ab.ss, 0.48, 1e-13, "swapped AB");
}

TEST(TwoWayAnovaTest, UnbalancedTypeIMatchesTheSequentialFormulas) {
  const Data d = Unbalanced();
  TwoWayOptions o;
  o.type = SumOfSquaresType::kTypeI;
  const TwoWayAnovaResult r = TwoWayAnova(d.y, d.a, d.b, o);
  ExpectRel(r.a.ss, 4.9, 1e-13, "A");
  ExpectRel(r.b.ss, 38.72, 1e-13, "B|A");
  ExpectRel(r.ab.ss, 0.48, 1e-13, "AB|A,B");
  ExpectRel(r.a.ss + r.b.ss + r.ab.ss + r.error.ss, r.ss_total, 1e-13, "sum");
  // B first: column means 3 (n 3) and 48/7 (n 7): SS_B = 3 * 2.7^2 + 7 * (81/70)^2.
  const TwoWayAnovaResult swapped = TwoWayAnova(d.y, d.b, d.a, o);
  const double ss_b = 3 * 2.7 * 2.7 + 6561.0 / 700;
  ExpectRel(swapped.a.ss, ss_b, 1e-13, "B first");
  ExpectRel(swapped.b.ss, 44.1 - ss_b - 0.48, 1e-13, "A|B");
}

void ExpectInvalid(const Data& d, const std::string& needle) {
  try {
    TwoWayAnova(d.y, d.a, d.b);
    ADD_FAILURE() << "expected std::invalid_argument mentioning " << needle;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(TwoWayAnovaTest, BadInputNamesTheProblem) {
  Data d = Unbalanced();
  d.b.pop_back();
  ExpectInvalid(d, "must pair one to one");

  d = Unbalanced();
  d.y[3] = std::nan("");
  ExpectInvalid(d, "observation 3 (A = \"a2\", B = \"b2\") is NaN");

  d = Unbalanced();
  d.a[0] = "";
  ExpectInvalid(d, "observation 0 has an empty A label");

  d = Unbalanced();
  d.a.assign(d.a.size(), "same");
  ExpectInvalid(d, "factor A has only 1 level (\"same\")");

  d = Unbalanced();  // remove the only (a2, b1) observation
  d.y.erase(d.y.begin() + 7);
  d.a.erase(d.a.begin() + 7);
  d.b.erase(d.b.begin() + 7);
  ExpectInvalid(d, "cell A = \"a2\", B = \"b1\" has no observations");

  ExpectInvalid(Data{{1, 2, 3, 4}, {"x", "x", "y", "y"}, {"p", "q", "p", "q"}},
                "leave no degrees of freedom for error");
  ExpectInvalid(Data{{1, 1, 2, 3, 4}, {"x", "x", "x", "y", "y"}, {"p", "p", "q", "p", "q"}},
                "every cell is constant");
}

}  // namespace
}  // namespace hoof::stats
