// The Statistics section of a real page, read in headless Chromium (Debian's `chromium`): a
// small rendered study whose e by surface fails Bartlett's test, so that the statistics step
// analyses it on a Box-Cox scale (catalog study "stats_transformed", tests/support/
// test_studies.h). The page must show the stored Bartlett p, name the transform, and print LSD
// letters that agree with the stored LSD pairs: two groups share a letter exactly when the pair
// is not significant, and "a" holds the highest mean.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "format/number_format.h"
#include "report/html_report.h"
#include "stats/compact_letters.h"
#include "studyfile/stats_tables.h"
#include "support/run_command.h"
#include "support/test_studies.h"
#include "support/test_util.h"

namespace hoof::report {
namespace {

namespace fs = std::filesystem;
using hoof::testing::ReadAll;
using hoof::testing::RunHoofimpact;

fs::path Root() {
  return fs::path(HOOF_BINARY_DIR) / "stats_report_test" / std::to_string(::getpid());
}

/// The page's DOM after its scripts ran, from headless Chromium.
std::string DumpDom(const fs::path& page) {
  const fs::path dir = Root() / "chromium";
  fs::create_directories(dir);
  const std::string cmd =
      "cd " + dir.string() +
      " && timeout 60 chromium --headless --no-sandbox --disable-gpu --disable-quic "
      "--no-first-run --disable-background-networking --disable-component-update --disable-sync "
      "--user-data-dir=" +
      (dir / "profile").string() + " --virtual-time-budget=5000 --dump-dom file://" +
      fs::absolute(page).string() + " >" + (dir / "dom.html").string() + " 2>" +
      (dir / "err.txt").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n" << ReadAll(dir / "err.txt");
  return ReadAll(dir / "dom.html");
}

/// The markup of the element with id `id`, up to the start of the next factor's part.
std::string Part(const std::string& dom, const std::string& id) {
  const std::size_t start = dom.find("id=\"" + id + "\"");
  if (start == std::string::npos) return "";
  const std::size_t end = dom.find("<div class=\"factor\"", start + 1);
  return dom.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

/// The study file the test runs.
fs::path H5() { return Root() / "out" / "study.h5"; }

/// e by surface as stored.
studyfile::StoredFactor Stored() {
  for (const auto& r : studyfile::ReadStatistics(H5()).responses)
    if (r.response == "e")
      for (const auto& f : r.factors)
        if (f.factor == "surface") return f;
  ADD_FAILURE() << "no e by surface in " << H5();
  return {};
}

/// The Bartlett result shown is the stored one, and rejects.
void CheckBartlett(const studyfile::StoredFactor& f, const std::string& part) {
  // The study exists for this: Bartlett rejects equal variances of e across the surfaces.
  double p = std::nan("");
  for (const auto& t : f.original.tests.rows)
    if (t.test == "bartlett") p = t.p;
  ASSERT_LT(p, 0.05) << "the catalog study no longer rejects; choose another seed";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      part, m, std::regex("<span class=\"bartlett-result\" data-p=\"([^\"]+)\">([^<]*)</span>")))
      << part.substr(0, 3000);
  EXPECT_NEAR(std::stod(m[1].str()), p, 1e-12 * p);
  // The text a reader sees: "K² = ..., df = 2, p = 0.0xx" (or "p < 0.001"), in the policy's form.
  std::string shown = format::PValue(p);
  if (shown.find('<') != std::string::npos) shown.replace(shown.find('<'), 1, "&lt;");
  EXPECT_NE(m[2].str().find(shown), std::string::npos) << m[2].str() << " / " << shown;
  EXPECT_NE(part.find("equal variances rejected"), std::string::npos);
}

/// The transform is named, and the ANOVA is on it.
void CheckTransform(const studyfile::StoredFactor& f, const std::string& part) {
  ASSERT_TRUE(f.transform.applied) << f.transform.decision;
  ASSERT_TRUE(f.transformed.has_value());
  // The stored formula in y, written in e.
  const std::string formula = std::regex_replace(f.transform.formula, std::regex("\\by\\b"), "e");
  EXPECT_NE(part.find("Box-Cox"), std::string::npos);
  EXPECT_NE(part.find("<span class=\"transform-formula\">" + formula + "</span>"),
            std::string::npos)
      << formula << "\n"
      << part.substr(0, 4000);
  EXPECT_NE(part.find("One-way ANOVA of " + formula + " by surface"), std::string::npos);
  EXPECT_NE(part.find("not the result"), std::string::npos);
}

/// The letters shown agree with the stored LSD pairs of the analysed scale.
void CheckLetters(const studyfile::StoredFactor& f, const std::string& part) {
  ASSERT_TRUE(f.transformed.has_value());
  const studyfile::StoredScale& s = *f.transformed;
  std::map<std::string, std::string> shown;
  const std::regex cell("<td class=\"lsd-letters\" data-group=\"([^\"]+)\">([^<]*)</td>");
  for (auto it = std::sregex_iterator(part.begin(), part.end(), cell); it != std::sregex_iterator();
       ++it)
    shown[(*it)[1].str()] = (*it)[2].str();
  ASSERT_EQ(shown.size(), s.groups.rows.size()) << part.substr(0, 4000);
  const auto share = [&](const std::string& a, const std::string& b) {
    for (const char c : shown.at(a))
      if (shown.at(b).find(c) != std::string::npos) return true;
    return false;
  };
  // Independently of how the letters were found: a pair shares a letter exactly when the stored
  // LSD does not call it significant (no stored pair: the LSD did not run, nothing differs).
  std::map<std::pair<std::string, std::string>, bool> different;
  for (const auto& r : s.lsd.rows) different[{r.a, r.b}] = r.significant;
  int significant = 0;
  for (std::size_t i = 0; i < s.groups.rows.size(); ++i)
    for (std::size_t j = i + 1; j < s.groups.rows.size(); ++j) {
      const std::string& a = s.groups.rows[i].group;
      const std::string& b = s.groups.rows[j].group;
      const bool diff = different.count({a, b}) ? different[{a, b}] : different[{b, a}];
      significant += diff;
      EXPECT_EQ(share(a, b), !diff) << a << " " << shown[a] << ", " << b << " " << shown[b];
    }
  EXPECT_GT(significant, 0) << "the study's surfaces should differ in e";
  // "a" is a letter of the highest mean on the analysed scale.
  const auto top = std::max_element(s.groups.rows.begin(), s.groups.rows.end(),
                                    [](const auto& x, const auto& y) { return x.mean < y.mean; });
  EXPECT_NE(shown.at(top->group).find('a'), std::string::npos) << top->group;
  // And they are the display of the stored means and pairs.
  std::vector<std::string> labels;
  std::vector<double> means;
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const auto& g : s.groups.rows) labels.push_back(g.group), means.push_back(g.mean);
  for (const auto& r : s.lsd.rows)
    if (r.significant) pairs.emplace_back(r.a, r.b);
  const stats::LetterDisplay d = stats::CompactLetters(labels, means, pairs);
  for (std::size_t g = 0; g < labels.size(); ++g) EXPECT_EQ(shown[labels[g]], d.letters[g]);
}

/// No raw key is left as a column name.
void CheckColumnNames(const std::string& dom) {
  const std::size_t start = dom.find("<section id=\"statistics\"");
  ASSERT_NE(start, std::string::npos);
  const std::string section = dom.substr(start, dom.find("</section>", start) - start);
  for (const char* raw :
       {"<th>ss</th>", "<th>ms</th>", "<th>f</th>", "eta_squared", "|0<", "|20<", "<th>cell</th>"})
    EXPECT_EQ(section.find(raw), std::string::npos) << raw;
  for (const char* plain : {"<th>Source</th>", "<th>Sum of squares</th>", "<th>Mean square</th>",
                            "<th>η²</th>", "dimensionless"})
    EXPECT_NE(section.find(plain), std::string::npos) << plain;
}

// synth -> run -> report, then the page in Chromium: one test, so that the study is run once.
TEST(StatsReportTest, ThePageStatesBartlettTheTransformAndTheLetters) {
  fs::remove_all(Root());
  auto r = RunHoofimpact("run " + hoof::testing::TestStudyDir("stats_transformed").string() +
                         " -o " + (Root() / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  r = RunHoofimpact("report " + H5().string() + " -o " + (Root() / "report").string() +
                    " --replay-trials 0");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const std::string dom = DumpDom(Root() / "report" / "report.html");
  const std::string part = Part(dom, "stats-e-surface");
  ASSERT_FALSE(part.empty()) << dom.substr(0, 2000);
  const studyfile::StoredFactor f = Stored();
  {
    SCOPED_TRACE("Bartlett");
    CheckBartlett(f, part);
  }
  {
    SCOPED_TRACE("transform");
    CheckTransform(f, part);
  }
  {
    SCOPED_TRACE("letters");
    CheckLetters(f, part);
  }
  {
    SCOPED_TRACE("column names");
    CheckColumnNames(dom);
  }
  fs::remove_all(Root());
}

}  // namespace
}  // namespace hoof::report
