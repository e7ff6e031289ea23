// The report's Statistics section from hand-built /stats tables (fast, no rendering): the test
// chain in its order, the ANOVA on the transformed scale as the result and the original one
// labelled as not, plain column names, "steel, 20°" cells, n/a for a one-trial s.d., and the
// LSD letters written out by hand. The page of a rendered study is checked in Chromium by
// stats_report_test.cc.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "report/html_parts.h"
#include "studyfile/stats_tables.h"

namespace hoof::report {
namespace {

using namespace studyfile;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<AnovaRow> Anova(double ss_b, double ss_w, std::size_t k, std::size_t n, double f,
                            double p) {
  return {{"between", k - 1, ss_b, ss_b / static_cast<double>(k - 1), f, p, ss_b / (ss_b + ss_w)},
          {"within", n - k, ss_w, ss_w / static_cast<double>(n - k), kNaN, kNaN, kNaN},
          {"total", n - 1, ss_b + ss_w, kNaN, kNaN, kNaN, kNaN}};
}

/// e by surface, Bartlett rejecting (p = 0.0172) and the reciprocal transform applied; on the
/// transformed scale steel differs from asphalt and concrete, which do not differ: steel "a",
/// asphalt and concrete "b". e by angle: nothing significant, no transform, no LSD. One cell of
/// a single trial.
StoredStatistics Stored() {
  StoredStatistics s;
  s.description =
      "hoofimpact stats: e and mu_eff by surface, angle and speed (alpha 0.05, "
      "two-way III)";
  StoredResponse r;
  r.response = "e";
  r.cells.description = "e: mean (s.d., n) per surface x angle, every measured trial";
  r.cells.rows = {{"e", "steel|0", "steel", "0", 2, 0.85, 0.041},
                  {"e", "steel|20", "steel", "20", 1, 0.80, 0.0}};
  StoredFactor surface;
  surface.factor = "surface";
  surface.original.groups.rows = {
      {"steel", 3, 0.8333, 0.04}, {"asphalt", 3, 0.60, 0.12}, {"concrete", 3, 0.70, 0.03}};
  surface.original.anova.rows = Anova(0.0822, 0.0338, 3, 9, 7.29, 0.0248);
  surface.original.tests.rows = {{"bartlett", 8.13, 2, kNaN, 0.0172, ""},
                                 {"welch", 5.1, 2, 3.9, 0.081, ""}};
  surface.transform = {
      "Bartlett p = 0.0172 < alpha = 0.05: ...", true, true, "1 - 1/y", -0.83, -1, 0, -2.6, 0.93};
  StoredScale t;
  t.groups.rows = {
      {"steel", 3, -0.2, 0.05}, {"asphalt", 3, -0.70, 0.10}, {"concrete", 3, -0.43, 0.06}};
  t.anova.rows = Anova(0.38, 0.036, 3, 9, 31.7, 0.00064);
  t.tests.rows = {{"bartlett", 0.9, 2, kNaN, 0.64, ""}, {"welch", 22.4, 2, 3.8, 0.00077, ""}};
  t.lsd.description = "Fisher's LSD pairs (unadjusted)";
  t.lsd.rows = {
      {"steel - asphalt", "steel", "asphalt", 0.5, 0.063, 7.9, 6, 0.0002, 0.35, 0.65, true},
      {"steel - concrete", "steel", "concrete", 0.23, 0.063, 3.6, 6, 0.011, 0.08, 0.38, true},
      {"asphalt - concrete", "asphalt", "concrete", -0.27, 0.063, -4.3, 6, 0.06, -0.42, 0.01,
       false}};
  surface.transformed = t;
  StoredFactor angle;
  angle.factor = "angle";
  angle.original.groups.rows = {{"0", 4, 0.75, 0.1}, {"20", 5, 0.70, 0.12}};
  angle.original.anova.rows = Anova(0.0056, 0.11, 2, 9, 0.36, 0.57);
  angle.original.tests.rows = {{"bartlett", 0.1, 1, kNaN, 0.75, ""},
                               {"welch", 0.37, 1, 6.9, 0.56, ""}};
  angle.original.lsd.description = "Fisher's LSD not performed: not performed: ANOVA p = ...";
  angle.transform = {
      "Bartlett p = 0.75 >= alpha = 0.05: ...", false, false, "", kNaN, kNaN, kNaN, kNaN, kNaN};
  r.factors = {surface, angle};
  r.two_way = StoredTable<TwoWayRow>{"Type III two-way ANOVA, surface x angle",
                                     {{"surface", 1, 0.05, 0.05, 6.1, 0.04},
                                      {"angle", 1, 0.01, 0.01, 1.2, 0.3},
                                      {"surface x angle", 1, 0.001, 0.001, 0.1, 0.76},
                                      {"error", 5, 0.04, 0.008, kNaN, kNaN}}};
  s.responses = {r};
  return s;
}

std::size_t At(const std::string& html, const std::string& text) {
  const std::size_t at = html.find(text);
  EXPECT_NE(at, std::string::npos) << "missing: " << text;
  return at;
}

/// The text of the element with id `id` (from its start tag to the next `</table>`).
std::string Table(const std::string& html, const std::string& id) {
  const std::size_t start = At(html, "id=\"" + id + "\"");
  if (start == std::string::npos) return "";
  return html.substr(start, html.find("</table>", start) - start);
}

TEST(StatsHtmlTest, TheTestChainInItsOrderWithTheTransformedAnovaAsTheResult) {
  const std::string html = internal::StatsHtml(Stored());
  // Bartlett, then the transform, then the ANOVA on the transformed scale, then the letters,
  // and only after them the original scale, labelled as not the result.
  const std::size_t bartlett = At(html, "K&sup2; = 8.13, df = 2, p = 0.017");
  const std::size_t rejected = At(html, "equal variances rejected</b> at &alpha; = 0.05");
  const std::size_t transform = At(html, "maximum-likelihood &lambda; = -0.830");
  const std::size_t scale = At(html,
                               "The analysis below is on the transformed scale, "
                               "<span class=\"transform-formula\">1 - 1/e</span>");
  const std::size_t anova = At(html, "One-way ANOVA of 1 - 1/e by surface");
  const std::size_t letters = At(html, "id=\"stats-e-surface-letters\"");
  const std::size_t original = At(html, "<b>not the result</b>");
  EXPECT_LT(bartlett, rejected);
  EXPECT_LT(rejected, transform);
  EXPECT_LT(transform, scale);
  EXPECT_LT(scale, anova);
  EXPECT_LT(anova, letters);
  EXPECT_LT(letters, original);
  // The result's table holds the transformed scale's F and p, Welch's beside it.
  const std::string result = Table(html, "stats-e-surface-anova");
  EXPECT_NE(result.find(">31.7<"), std::string::npos) << result;
  EXPECT_NE(result.find("&lt; 0.001"), std::string::npos) << result;
  EXPECT_EQ(result.find(">7.29<"), std::string::npos) << result;  // the original F is not there
  EXPECT_NE(Table(html, "stats-e-surface-welch").find(">22.4<"), std::string::npos);
  // The original F is, after the "not the result" label.
  EXPECT_GT(html.find(">7.29<"), original);
  // Bartlett again on the transformed scale.
  EXPECT_NE(html.find("Bartlett on it: K&sup2; = 0.900, df = 2, p = 0.640 (no longer rejected)"),
            std::string::npos);
  // The conclusion, in one line.
  EXPECT_NE(html.find("<b>surface affects e</b> (ANOVA on 1 - 1/e, p &lt; 0.001; Welch p &lt; "
                      "0.001)."),
            std::string::npos);
  EXPECT_NE(html.find("No significant effect of angle on e (ANOVA, p = 0.570; Welch p = 0.560)."),
            std::string::npos);
}

TEST(StatsHtmlTest, LettersAsPapersPrintThem) {
  const std::string html = internal::StatsHtml(Stored());
  // Steel differs from both, asphalt and concrete do not differ: steel a, the others b; rows by
  // the analysed mean, highest first.
  const std::string t = Table(html, "stats-e-surface-letters");
  const std::size_t steel = At(t, "data-group=\"steel\">a</td>");
  const std::size_t concrete = At(t, "data-group=\"concrete\">b</td>");
  const std::size_t asphalt = At(t, "data-group=\"asphalt\">b</td>");
  EXPECT_LT(steel, concrete);
  EXPECT_LT(concrete, asphalt);
  // Both means: e as measured and on the transformed scale.
  EXPECT_NE(t.find("<th>Mean e</th>"), std::string::npos);
  EXPECT_NE(t.find("<th>Mean of 1 - 1/e</th>"), std::string::npos);
  EXPECT_NE(t.find(">0.8333<"), std::string::npos) << t;
  EXPECT_NE(t.find(">-0.2000<"), std::string::npos) << t;
  // No LSD by angle: every group "a", and the page says why.
  const std::string a = Table(html, "stats-e-angle-letters");
  EXPECT_NE(a.find("data-group=\"0\">a</td>"), std::string::npos);
  EXPECT_NE(a.find("data-group=\"20\">a</td>"), std::string::npos);
  EXPECT_NE(html.find("every group carries the letter a"), std::string::npos);
}

TEST(StatsHtmlTest, PlainColumnNamesCellsAndUnits) {
  const std::string html = internal::StatsHtml(Stored());
  for (const char* header :
       {"<th>Source</th>", "<th>df</th>", "<th>Sum of squares</th>", "<th>Mean square</th>",
        "<th>F</th>", "<th>p</th>", "<th>&eta;&sup2;</th>"})
    EXPECT_NE(html.find(header), std::string::npos) << header;
  for (const char* raw : {"<th>ss</th>", "<th>ms</th>", "<th>f</th>", "eta_squared", "steel|"})
    EXPECT_EQ(html.find(raw), std::string::npos) << raw;
  EXPECT_NE(html.find("dimensionless"), std::string::npos);
  // The one-trial cell: its s.d. is undefined.
  const std::string cells = Table(html, "stats-e-cells");
  EXPECT_NE(cells.find("<td>steel, 20&deg;</td><td class=\"num\">1</td><td class=\"num\">0.8000"
                       "</td><td class=\"num\">n/a</td>"),
            std::string::npos)
      << cells;
  EXPECT_NE(cells.find("<td>steel, 0&deg;</td><td class=\"num\">2</td><td class=\"num\">0.8500"
                       "</td><td class=\"num\">0.041</td>"),
            std::string::npos)
      << cells;
  // The two-way table, its interaction written with a times sign.
  EXPECT_NE(html.find("<td>Surface \xC3\x97 angle</td>"), std::string::npos);
  EXPECT_NE(html.find("Type III two-way ANOVA, surface x angle (on e as measured)"),
            std::string::npos);
}

// A response without trials (mu_eff of a study of normal impacts) says so, with no empty tables.
TEST(StatsHtmlTest, AResponseWithoutTrialsSaysSo) {
  StoredStatistics s = Stored();
  StoredResponse mu;
  mu.response = "mu_eff";
  mu.cells.description = "mu_eff: mean (s.d., n) per surface x angle, successful oblique trials";
  mu.notes = {{"two_way", ""}};
  s.responses.push_back(mu);
  const std::string html = internal::StatsHtml(s);
  const std::size_t start = At(html, "id=\"stats-mu_eff\"");
  ASSERT_NE(start, std::string::npos);
  const std::string part = html.substr(start);
  EXPECT_NE(part.find("No trial to analyse."), std::string::npos) << part;
  EXPECT_EQ(part.find("<table"), std::string::npos) << part;
}

TEST(StatsHtmlTest, AnLsdPairOfAnUnknownGroupIsAnError) {
  StoredStatistics s = Stored();
  s.responses[0].factors[0].transformed->lsd.rows[0].b = "gravel";
  EXPECT_THROW(internal::StatsHtml(s), std::invalid_argument);
}

}  // namespace
}  // namespace hoof::report
