// The compact letter display: worked examples written out by hand, and the defining properties
// checked over many seeded random significance matrices.
#include "stats/compact_letters.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::stats {
namespace {

using Matrix = std::vector<std::vector<bool>>;

/// The k x k matrix with the (0-based) pairs `pairs` significantly different.
Matrix Different(std::size_t k, const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  Matrix m(k, std::vector<bool>(k, false));
  for (const auto& [i, j] : pairs) m[i][j] = m[j][i] = true;
  return m;
}

/// Whether groups i and j carry a common letter (by the letters as printed).
bool ShareALetter(const LetterDisplay& d, std::size_t i, std::size_t j) {
  for (const auto& column : d.columns)
    if (std::count(column.begin(), column.end(), i) && std::count(column.begin(), column.end(), j))
      return true;
  return false;
}

// PlantGrowth (R's datasets; the data of fisher_lsd_test.cc): means ctrl 5.032, trt1 4.661,
// trt2 5.526, and at alpha = 0.05 Fisher's LSD separates only trt1 from trt2 (p = 0.0045; ctrl
// against the others p = 0.194 and 0.088). By hand: the column {ctrl, trt1, trt2} splits into
// {ctrl, trt2} and {ctrl, trt1}; the first holds the highest mean (trt2), so it is "a". The
// display papers print: trt2 a, ctrl ab, trt1 b.
TEST(CompactLettersTest, PlantGrowthLsdGroups) {
  const LetterDisplay d = CompactLetters({5.032, 4.661, 5.526}, Different(3, {{1, 2}}));
  EXPECT_EQ(d.letters, (std::vector<std::string>{"ab", "b", "a"}));
  ASSERT_EQ(d.columns.size(), 2u);
  EXPECT_EQ(d.columns[0], (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(d.columns[1], (std::vector<std::size_t>{0, 1}));
}

// Gramm, Guo, Hueffner, Niedermeier, Piepho and Schmid (2007), Fig. 2: five treatments with
// the significant pairs {1,5}, {2,3}, {2,5}, {3,5}. Worked by hand (treatments 1..5 are
// indices 0..4, means falling with the index):
//   {12345} -(1,5)-> {2345} {1234} -(2,3)-> {345} {245} {134} {124}
//   -(2,5)-> {345} {45} {24} {134} {124}, absorbed: {345} {134} {124}
//   -(3,5)-> {45} {34} {134} {124}, absorbed: {45} {134} {124}; sweeping drops nothing.
// That is three letters, the minimum (the paper's clique cover of the graph of the
// non-significant pairs has three cliques). Named by the means: {124} a, {134} b, {45} c.
TEST(CompactLettersTest, GrammEtAlFigure2) {
  const LetterDisplay d =
      CompactLetters({5, 4, 3, 2, 1}, Different(5, {{0, 4}, {1, 2}, {1, 4}, {2, 4}}));
  EXPECT_EQ(d.letters, (std::vector<std::string>{"ab", "a", "b", "abc", "c"}));
}

// Sweeping: significant pairs (1,4), (1,5), (2,5) of five treatments, means falling with the
// index. Insert-and-absorb by hand:
//   {12345} -(1,4)-> {2345} {1235} -(1,5)-> {2345} {235} {123}, absorbed: {2345} {123}
//   -(2,5)-> {345} {234} {123}.
// Treatment 3 carries all three letters; in {234} its letter is redundant (3 meets 2 in {123}
// and 4 in {345}), so the sweep removes it: {345} {24} {123}. Named by the means: {123} a,
// {24} b, {345} c, so 1 a, 2 ab, 3 ac, 4 bc, 5 c.
TEST(CompactLettersTest, SweepingDropsARedundantLetter) {
  const LetterDisplay d = CompactLetters({5, 4, 3, 2, 1}, Different(5, {{0, 3}, {0, 4}, {1, 4}}));
  EXPECT_EQ(d.letters, (std::vector<std::string>{"a", "ab", "ac", "bc", "c"}));
}

// Four groups, A > B > C > D, with only A-B and C-D different: no order of the groups lets the
// letters run in unbroken stretches; every non-significant pair is a letter of its own:
// {A,C} a, {A,D} b, {B,C} c, {B,D} d.
TEST(CompactLettersTest, CrossedPairsNeedFourLetters) {
  const LetterDisplay d = CompactLetters({4, 3, 2, 1}, Different(4, {{0, 1}, {2, 3}}));
  EXPECT_EQ(d.letters, (std::vector<std::string>{"ab", "cd", "ac", "bd"}));
}

TEST(CompactLettersTest, NoneOrAllDifferent) {
  EXPECT_EQ(CompactLetters({1, 3, 2}, Different(3, {})).letters,
            (std::vector<std::string>{"a", "a", "a"}));
  // All different: one letter each, "a" for the highest mean (group 1), then group 2, group 0.
  EXPECT_EQ(CompactLetters({1, 3, 2}, Different(3, {{0, 1}, {0, 2}, {1, 2}})).letters,
            (std::vector<std::string>{"c", "a", "b"}));
  EXPECT_EQ(CompactLetters({7}, Different(1, {})).letters, (std::vector<std::string>{"a"}));
}

TEST(CompactLettersTest, LetterNames) {
  EXPECT_EQ(LetterName(0), "a");
  EXPECT_EQ(LetterName(25), "z");
  EXPECT_EQ(LetterName(26), "A");
  EXPECT_EQ(LetterName(51), "Z");
  EXPECT_EQ(LetterName(52), "{53}");
}

TEST(CompactLettersTest, BadInputIsRejected) {
  EXPECT_THROW(CompactLetters({}, {}), std::invalid_argument);
  EXPECT_THROW(CompactLetters({1, 2}, Different(3, {})), std::invalid_argument);
  Matrix asymmetric = Different(2, {});
  asymmetric[0][1] = true;
  EXPECT_THROW(CompactLetters({1, 2}, asymmetric), std::invalid_argument);
  Matrix diagonal = Different(2, {});
  diagonal[1][1] = true;
  EXPECT_THROW(CompactLetters({1, 2}, diagonal), std::invalid_argument);
  EXPECT_THROW(CompactLetters({1, std::nan("")}, Different(2, {})), std::invalid_argument);
}

// The defining properties over seeded random matrices of 1 to 10 groups and every density:
//  - two groups share a letter exactly when they are not significantly different;
//  - every group has a letter, and the printed letters are those of the columns;
//  - no letter's groups lie within another letter's (nothing left to absorb);
//  - letters run by the means: letter l's highest mean is at least letter l+1's, and "a"
//    holds a group of the highest mean.
TEST(CompactLettersTest, PropertiesHoldOnRandomMatrices) {
  std::mt19937 rng(20260415);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const std::size_t k = 1 + static_cast<std::size_t>(trial % 10);
    const double density = unit(rng);
    Matrix m(k, std::vector<bool>(k, false));
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = i + 1; j < k; ++j) m[i][j] = m[j][i] = unit(rng) < density;
    // Means on a coarse grid, so that ties occur.
    std::vector<double> means(k);
    for (double& x : means) x = std::floor(unit(rng) * 6.0);
    const LetterDisplay d = CompactLetters(means, m);
    ASSERT_EQ(d.letters.size(), k);
    for (std::size_t i = 0; i < k; ++i) {
      EXPECT_FALSE(d.letters[i].empty()) << "trial " << trial << " group " << i;
      std::string expected;
      for (std::size_t l = 0; l < d.columns.size(); ++l)
        if (std::count(d.columns[l].begin(), d.columns[l].end(), i)) expected += LetterName(l);
      EXPECT_EQ(d.letters[i], expected);
      for (std::size_t j = i + 1; j < k; ++j)
        EXPECT_EQ(ShareALetter(d, i, j), !m[i][j]) << "trial " << trial << " pair " << i << j;
    }
    for (std::size_t a = 0; a < d.columns.size(); ++a)
      for (std::size_t b = 0; b < d.columns.size(); ++b)
        if (a != b) {
          EXPECT_FALSE(std::includes(d.columns[b].begin(), d.columns[b].end(), d.columns[a].begin(),
                                     d.columns[a].end()))
              << "trial " << trial << ": letter " << a << " lies within letter " << b;
        }
    std::vector<double> top;
    for (const auto& column : d.columns) {
      double best = -1;
      for (std::size_t g : column) best = std::max(best, means[g]);
      top.push_back(best);
    }
    EXPECT_TRUE(std::is_sorted(top.rbegin(), top.rend())) << "trial " << trial;
    EXPECT_EQ(top.front(), *std::max_element(means.begin(), means.end()));
    ++checked;
  }
  EXPECT_EQ(checked, 4000);
}

}  // namespace
}  // namespace hoof::stats
