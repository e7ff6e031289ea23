// Grouping, validation and group summaries; summaries against hand-computed values.
#include "stats/grouping.h"

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::stats {
namespace {

void ExpectMessage(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "expected std::invalid_argument mentioning " << needle;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(GroupingTest, GroupsKeepTheOrderOfFirstAppearance) {
  const GroupedData d = GroupByLabel({1, 2, 3, 4, 5, 6}, {"z", "a", "z", "m", "a", "z"});
  ASSERT_EQ(d.groups(), 3u);
  EXPECT_EQ(d.labels, (std::vector<std::string>{"z", "a", "m"}));
  EXPECT_EQ(d.values[0], (std::vector<double>{1, 3, 6}));
  EXPECT_EQ(d.values[1], (std::vector<double>{2, 5}));
  EXPECT_EQ(d.values[2], (std::vector<double>{4}));
  EXPECT_EQ(d.observations(), 6u);
}

TEST(GroupingTest, SummariesMatchHandValues) {
  // {1, 2, 3, 4}: mean 2.5, variance (2.25 + 0.25 + 0.25 + 2.25) / 3 = 5/3.
  // {10, 10, 13}: mean 11, variance (1 + 1 + 4) / 2 = 3.
  const auto s = Summarize(MakeGroups({"a", "b"}, {{1, 2, 3, 4}, {10, 10, 13}}));
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].label, "a");
  EXPECT_EQ(s[0].n, 4u);
  EXPECT_DOUBLE_EQ(s[0].mean, 2.5);
  EXPECT_DOUBLE_EQ(s[0].variance, 5.0 / 3.0);
  EXPECT_DOUBLE_EQ(s[0].sd, std::sqrt(5.0 / 3.0));
  EXPECT_DOUBLE_EQ(s[1].mean, 11.0);
  EXPECT_DOUBLE_EQ(s[1].variance, 3.0);
}

TEST(GroupingTest, StiffDataKeepTheirMeans) {
  // 1000000000000.5 and 1000000000001.5 are exact in double; their mean is exact too.
  const auto s = Summarize(MakeGroups({"a", "b"}, {{1e12 + 0.5, 1e12 + 1.5}, {3.0, 5.0}}));
  EXPECT_EQ(s[0].mean, 1e12 + 1.0);
  EXPECT_DOUBLE_EQ(s[0].variance, 0.5);
  EXPECT_DOUBLE_EQ(s[1].variance, 2.0);
}

TEST(GroupingTest, BadInputNamesTheProblem) {
  ExpectMessage([] { GroupByLabel({1, 2}, {"a"}); }, "response has 2 values but there are 1");
  ExpectMessage([] { GroupByLabel({}, {}); }, "no observations");
  ExpectMessage([] { GroupByLabel({1, 2}, {"a", ""}); }, "observation 1 has an empty group label");
  ExpectMessage([] { GroupByLabel({1, INFINITY}, {"a", "b"}); }, "(group \"b\") is infinite");
  ExpectMessage([] { MakeGroups({"a", "a"}, {{1}, {2}}); }, "distinct");
  ExpectMessage([] { MakeGroups({"a", "b"}, {{1}, {}}); }, "group \"b\" has no observations");
}

TEST(GroupingTest, ValidateOneWayNamesTheGroup) {
  ExpectMessage([] { ValidateOneWay(MakeGroups({"x"}, {{1, 2}})); }, "found 1 (\"x\")");
  ExpectMessage(
      [] {
        ValidateOneWay(MakeGroups({"x", "y"}, {{1, 2}, {3}}));
      },
      "group \"y\" has 1 observation");
  ExpectMessage(
      [] {
        ValidateOneWay(MakeGroups({"x", "y"}, {{7, 7}, {7, 7}}));
      },
      "all 4 observations equal 7");
  EXPECT_NO_THROW(ValidateOneWay(MakeGroups({"x", "y"}, {{1, 2}, {3, 3}})));
}

}  // namespace
}  // namespace hoof::stats
