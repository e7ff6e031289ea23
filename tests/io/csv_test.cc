#include "io/csv.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "support/test_util.h"

namespace hoof::io {
namespace {

CsvTable ParseText(const std::string& text) {
  std::istringstream in(text);
  return CsvTable::Parse(in, "test.csv");
}

const auto ExpectError = [](auto fn, const std::string& needle) {
  hoof::testing::ExpectErrorContaining(fn, needle);
};

TEST(CsvTest, ParsesQuotedFieldsAndNumbers) {
  const CsvTable t = ParseText(
      "surface,v_before_m_s,note\r\n"
      "steel,3.0,\"a, b\"\n"
      "\n"
      "\"con\"\"crete\",2.5e0,\"two\nlines\"\n");
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.Text(0, 2), "a, b");
  EXPECT_EQ(t.Text(1, 0), "con\"crete");
  EXPECT_EQ(t.Text(1, 2), "two\nlines");
  EXPECT_DOUBLE_EQ(t.Numbers("v_before_m_s")[1], 2.5);
  EXPECT_EQ(t.LineOf(1), 4u);
}

TEST(CsvTest, ErrorsNameFileLineAndColumn) {
  ExpectError([] { ParseText("a,b\n1,2\n3\n"); }, "test.csv:3");
  const CsvTable t = ParseText("a,b\n1,2\n3,x\n");
  ExpectError([&] { t.Numbers("b"); }, "test.csv:3: column \"b\" value \"x\"");
  ExpectError([&] { t.Column("c"); }, "no column \"c\" (columns: a, b)");
  const CsvTable n = ParseText("a\nnan\n");
  ExpectError([&] { n.Numbers("a"); }, "not a finite number");
  ExpectError([] { ParseText(""); }, "no header");
  ExpectError([] { CsvTable::Read("/nonexistent/x.csv"); }, "/nonexistent/x.csv");
}

TEST(CsvTest, NumbersRoundTripExactly) {
  for (double v : {0.1, 1.0 / 3.0, -2.5e-17, 6.02214076e23}) {
    const std::string s = CsvNumber(v);
    EXPECT_EQ(std::stod(s), v) << s;
  }
  EXPECT_EQ(CsvNumber(std::nan("")), "nan");
  EXPECT_EQ(CsvEscape("plain"), "plain");
  EXPECT_EQ(CsvEscape("a,\"b\""), "\"a,\"\"b\"\"\"");
}

}  // namespace
}  // namespace hoof::io
