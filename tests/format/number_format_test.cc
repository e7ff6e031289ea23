// The number-formatting policy (src/format/number_format.h): each expectation is written out by
// hand from the policy's rules, not computed with the library.
#include "format/number_format.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

namespace hoof::format {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(NumberFormatTest, UndefinedIsNaEverywhere) {
  EXPECT_EQ(Number(kNaN), "n/a");
  EXPECT_EQ(Number(-kInf, Kind::kStatistic), "n/a");
  EXPECT_EQ(P(kNaN), "n/a");
  EXPECT_EQ(PValue(kNaN), "p n/a");
  EXPECT_EQ(WithError(kNaN, 0.1), "n/a");
  EXPECT_EQ(Interval(kNaN, 1.0), "n/a");
  EXPECT_EQ(Interval(0.0, kInf), "n/a");
  EXPECT_EQ(Seconds(kNaN), "n/a");
}

TEST(NumberFormatTest, SignificantDigitsKeepTrailingZerosAndRoundUp) {
  EXPECT_EQ(Significant(0.7, 4), "0.7000");
  EXPECT_EQ(Significant(2.6776612, 4), "2.678");
  EXPECT_EQ(Significant(-0.0758621, 4), "-0.07586");
  EXPECT_EQ(Significant(9.99996, 4), "10.00");
  EXPECT_EQ(Significant(123456.0, 3), "123000");
  EXPECT_EQ(Significant(0.0, 3), "0.00");
  EXPECT_EQ(Significant(3.2e-7, 2), "3.2e-07");
  EXPECT_EQ(Significant(4.5e8, 2), "4.5e+08");
  EXPECT_THROW(Significant(1.0, 0), std::invalid_argument);
}

TEST(NumberFormatTest, KindsCarryTheirDigits) {
  EXPECT_EQ(Number(0.712345, Kind::kCoefficient), "0.7123");
  EXPECT_EQ(Number(12.3456, Kind::kStatistic), "12.3");
  EXPECT_EQ(Number(0.012345, Kind::kError), "0.012");
}

TEST(NumberFormatTest, PValuesInPaperStyle) {
  EXPECT_EQ(P(3.58018e-10), "< 0.001");
  EXPECT_EQ(P(0.0174), "0.017");
  EXPECT_EQ(P(0.001), "0.001");
  EXPECT_EQ(P(1.0), "1.000");
  EXPECT_EQ(PValue(3.58018e-10), "p < 0.001");
  EXPECT_EQ(PValue(0.0174), "p = 0.017");
}

// Discovery compares p with naming levels of 1e-4 and below: there a p keeps its digits.
TEST(NumberFormatTest, PAgainstASmallLevelKeepsItsDigits) {
  EXPECT_EQ(PAgainstSmallLevel(1.6e-8), "1.60e-08");
  EXPECT_EQ(PAgainstSmallLevel(3.6e-58), "3.60e-58");
  EXPECT_EQ(PAgainstSmallLevel(1e-320), "< 1e-300");
  EXPECT_EQ(PAgainstSmallLevel(0.0094), "0.0094");
  EXPECT_EQ(PAgainstSmallLevel(0.2), "0.2");
  EXPECT_EQ(PAgainstSmallLevel(1.0), "1");
  EXPECT_EQ(PAgainstSmallLevel(kNaN), "n/a");
}

TEST(NumberFormatTest, ValueToTheDecimalOfItsError) {
  EXPECT_EQ(WithError(0.71234, 0.01312, Kind::kCoefficient, " +- "), "0.712 +- 0.013");
  EXPECT_EQ(WithError(2.5, 0.25, Kind::kMeasured, " +- "), "2.50 +- 0.25");
  EXPECT_EQ(WithError(0.71234, kNaN, Kind::kCoefficient, " +- "), "0.7123");
  EXPECT_EQ(WithError(0.5, 0.0, Kind::kCoefficient, " +- "), "0.5000");
  EXPECT_EQ(WithError(0.5, 0.1), "0.50 \xC2\xB1 0.10");
}

TEST(NumberFormatTest, IntervalsAndDurations) {
  EXPECT_EQ(Interval(0.0601, 0.09123, Kind::kCoefficient), "0.06010 to 0.09123");
  EXPECT_EQ(Seconds(4.9795), "5.0 s");
  EXPECT_EQ(Seconds(0.0354), "35 ms");
}

}  // namespace
}  // namespace hoof::format
