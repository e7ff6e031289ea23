// The statistics as the terminal text, JSON and long CSV that `hoofimpact stats` prints and
// writes (docs/statistics.md, "The command"): of one response grouped by a factor, and of a
// whole study's tables.
#include "study/statistics_text.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "format/number_format.h"
#include "io/atomic_file.h"
#include "io/csv.h"
#include "stats/compact_letters.h"

namespace hoof::study {
namespace {

using nlohmann::json;

json JsonNumber(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }

json JsonGroups(const std::vector<stats::GroupSummary>& groups) {
  json out = json::array();
  for (const auto& g : groups)
    out.push_back(
        {{"label", g.label}, {"n", g.n}, {"mean", JsonNumber(g.mean)}, {"sd", JsonNumber(g.sd)}});
  return out;
}

json JsonAnova(const stats::OneWayAnovaResult& r) {
  return {
      {"between",
       {{"df", r.df_between},
        {"ss", JsonNumber(r.ss_between)},
        {"ms", JsonNumber(r.ms_between)},
        {"f", JsonNumber(r.f)},
        {"p", JsonNumber(r.p)}}},
      {"within",
       {{"df", r.df_within}, {"ss", JsonNumber(r.ss_within)}, {"ms", JsonNumber(r.ms_within)}}},
      {"total", {{"df", r.df_total}, {"ss", JsonNumber(r.ss_total)}}},
      {"eta_squared", JsonNumber(r.eta_squared)},
  };
}

/// Writes " value" right-aligned in `width` characters (the leading space keeps columns
/// apart even when a number needs more room).
template <typename T>
void Col(std::ostream& os, const T& value, int width) {
  os << ' ' << std::setw(width) << value;
}

void AnovaLine(std::ostream& os, const std::string& source, std::size_t df, double ss,
               std::optional<double> ms, std::optional<double> f, std::optional<double> p) {
  os << "    " << std::left << std::setw(20) << source << std::right;
  Col(os, df, 5);
  Col(os, format::Number(ss, format::Kind::kSum), 13);
  if (ms) Col(os, format::Number(*ms, format::Kind::kSum), 13);
  if (f) Col(os, format::Number(*f, format::Kind::kStatistic), 11);
  if (p) Col(os, format::P(*p), 12);
  os << "\n";
}

void AnovaHeader(std::ostream& os) {
  os << "    " << std::left << std::setw(20) << "source" << std::right;
  Col(os, "df", 5);
  Col(os, "SS", 13);
  Col(os, "MS", 13);
  Col(os, "F", 11);
  Col(os, "p", 12);
  os << "\n";
}

// CSV: one long table "table,row,statistic,value", so that tables of different shapes share
// one file.

class LongCsv {
 public:
  explicit LongCsv(std::ostream& out) : out_(out) { out_ << "table,row,statistic,value\n"; }
  void Add(const std::string& table, const std::string& row, const std::string& statistic,
           double value) {
    out_ << io::CsvEscape(table) << "," << io::CsvEscape(row) << "," << statistic << ","
         << io::CsvNumber(value) << "\n";
  }

 private:
  std::ostream& out_;
};

void CsvScale(LongCsv& csv, const std::string& prefix, const stats::OneWayScaleResults& s) {
  for (const auto& g : s.groups) {
    csv.Add(prefix + "groups", g.label, "n", static_cast<double>(g.n));
    csv.Add(prefix + "groups", g.label, "mean", g.mean);
    csv.Add(prefix + "groups", g.label, "sd", g.sd);
  }
  const auto& a = s.anova;
  const std::string t = prefix + "anova";
  csv.Add(t, "between", "df", static_cast<double>(a.df_between));
  csv.Add(t, "between", "ss", a.ss_between);
  csv.Add(t, "between", "ms", a.ms_between);
  csv.Add(t, "between", "f", a.f);
  csv.Add(t, "between", "p", a.p);
  csv.Add(t, "within", "df", static_cast<double>(a.df_within));
  csv.Add(t, "within", "ss", a.ss_within);
  csv.Add(t, "within", "ms", a.ms_within);
  csv.Add(t, "total", "df", static_cast<double>(a.df_total));
  csv.Add(t, "total", "ss", a.ss_total);
  csv.Add(t, "total", "eta_squared", a.eta_squared);
  csv.Add(prefix + "bartlett", "test", "k_squared", s.bartlett.k_squared);
  csv.Add(prefix + "bartlett", "test", "df", static_cast<double>(s.bartlett.df));
  csv.Add(prefix + "bartlett", "test", "p", s.bartlett.p);
  if (s.welch) {
    csv.Add(prefix + "welch", "test", "f", s.welch->f);
    csv.Add(prefix + "welch", "test", "df1", s.welch->df1);
    csv.Add(prefix + "welch", "test", "df2", s.welch->df2);
    csv.Add(prefix + "welch", "test", "p", s.welch->p);
  }
  for (const auto& c : s.lsd) {
    const std::string row = c.group_a + " - " + c.group_b;
    csv.Add(prefix + "lsd", row, "difference", c.difference);
    csv.Add(prefix + "lsd", row, "standard_error", c.standard_error);
    csv.Add(prefix + "lsd", row, "t", c.t);
    csv.Add(prefix + "lsd", row, "df", static_cast<double>(c.df));
    csv.Add(prefix + "lsd", row, "p", c.p);
    csv.Add(prefix + "lsd", row, "ci_low", c.ci_low);
    csv.Add(prefix + "lsd", row, "ci_high", c.ci_high);
  }
}

/// "mean (s.d., n)" per surface (rows) x angle (columns), as in the paper's tables.
void WriteCells(std::ostream& os, const ResponseAnalysis& r) {
  std::vector<std::string> surfaces, angles;
  for (std::size_t i = 0; i < r.values.size(); ++i) {
    if (std::find(surfaces.begin(), surfaces.end(), r.surface[i]) == surfaces.end())
      surfaces.push_back(r.surface[i]);
    if (std::find(angles.begin(), angles.end(), r.angle[i]) == angles.end())
      angles.push_back(r.angle[i]);
  }
  os << "  mean (s.d., n) per surface x angle\n    " << std::left << std::setw(12) << "surface";
  for (const auto& angle : angles) os << std::setw(26) << (angle + " deg");
  os << std::right << "\n";
  for (const auto& surface : surfaces) {
    os << "    " << std::left << std::setw(12) << surface;
    for (const auto& angle : angles) {
      std::ostringstream cell;
      cell << std::setprecision(4);
      for (const auto& c : r.cells)
        if (c.label == surface + "|" + angle) {
          // The s.d. of a one-trial cell is undefined: "n/a" (as the report prints it), not 0.
          cell << format::Number(c.mean) << " (";
          if (c.n > 1)
            cell << format::Number(c.sd);
          else
            cell << format::kUndefined;
          cell << ", " << c.n << ")";
        }
      os << std::setw(26) << (cell.str().empty() ? "-" : cell.str());
    }
    os << std::right << "\n";
  }
}

}  // namespace

json OneWayJson(const stats::OneWayScaleResults& s, double alpha) {
  json lsd_pairs = json::array();
  for (const auto& c : s.lsd)
    lsd_pairs.push_back({{"a", c.group_a},
                         {"b", c.group_b},
                         {"difference", JsonNumber(c.difference)},
                         {"standard_error", JsonNumber(c.standard_error)},
                         {"t", JsonNumber(c.t)},
                         {"df", c.df},
                         {"p", JsonNumber(c.p)},
                         {"ci_low", JsonNumber(c.ci_low)},
                         {"ci_high", JsonNumber(c.ci_high)},
                         {"significant", c.significant}});
  json welch = nullptr;
  if (s.welch)
    welch = {{"f", JsonNumber(s.welch->f)},
             {"df1", JsonNumber(s.welch->df1)},
             {"df2", JsonNumber(s.welch->df2)},
             {"p", JsonNumber(s.welch->p)}};
  return {
      {"groups", JsonGroups(s.groups)},
      {"anova", JsonAnova(s.anova)},
      {"bartlett",
       {{"k_squared", JsonNumber(s.bartlett.k_squared)},
        {"df", s.bartlett.df},
        {"p", JsonNumber(s.bartlett.p)},
        {"rejects_equal_variances", s.bartlett.p < alpha},
        {"note", s.bartlett.note}}},
      {"welch", welch},
      {"welch_note", s.welch_note},
      {"lsd",
       {{"performed", s.lsd_performed},
        {"note", s.lsd_note},
        {"confidence", 1.0 - alpha},
        {"pairs", lsd_pairs}}},
  };
}

json TransformJson(const stats::TransformDecision& t, double alpha) {
  json out = {{"considered", t.considered}, {"applied", t.applied}, {"reason", t.reason}};
  if (t.box_cox) {
    const stats::BoxCoxResult& b = *t.box_cox;
    out["box_cox"] = {
        {"lambda_ml", JsonNumber(b.lambda_ml)},   {"ci_low", JsonNumber(b.ci_low)},
        {"ci_high", JsonNumber(b.ci_high)},       {"ci_low_at_limit", b.ci_low_at_limit},
        {"ci_high_at_limit", b.ci_high_at_limit}, {"lambda", JsonNumber(b.lambda)},
        {"shift", JsonNumber(b.shift)},           {"rule", b.rule}};
  }
  if (t.applied) out["formula"] = t.formula;
  if (t.rerun) out["rerun"] = OneWayJson(*t.rerun, alpha);
  return out;
}

json TwoWayJson(const stats::TwoWayAnovaResult& r) {
  const auto row = [](const stats::TwoWayRow& w, bool test) {
    json j = {
        {"source", w.source}, {"df", w.df}, {"ss", JsonNumber(w.ss)}, {"ms", JsonNumber(w.ms)}};
    if (test) {
      j["f"] = JsonNumber(w.f);
      j["p"] = JsonNumber(w.p);
    }
    return j;
  };
  json cells = json::array();
  for (std::size_t i = 0; i < r.levels_a.size(); ++i)
    for (std::size_t j = 0; j < r.levels_b.size(); ++j)
      cells.push_back({{"a", r.levels_a[i]},
                       {"b", r.levels_b[j]},
                       {"n", r.cell_counts[i][j]},
                       {"mean", JsonNumber(r.cell_means[i][j])}});
  return {
      {"ss_type", stats::ToString(r.type)},
      {"balanced", r.balanced},
      {"cells", cells},
      {"rows", json::array({row(r.a, true), row(r.b, true), row(r.ab, true), row(r.error, false)})},
      {"total", {{"df", r.df_total}, {"ss", JsonNumber(r.ss_total)}}}};
}

json StudyStatisticsJson(const StudyStatistics& s) {
  json excluded = json::array();
  for (const auto& [id, why] : s.excluded) excluded.push_back({{"id", id}, {"reason", why}});
  json responses = json::object();
  for (const auto& r : s.responses) {
    json cells = json::array();
    for (const auto& c : r.cells) {
      const auto bar = c.label.find('|');
      cells.push_back({{"surface", c.label.substr(0, bar)},
                       {"angle_deg", c.label.substr(bar + 1)},
                       {"n", c.n},
                       {"mean", JsonNumber(c.mean)},
                       {"sd", JsonNumber(c.sd)}});
    }
    json j = {{"selection", r.selection}, {"observations", r.values.size()}, {"cells", cells}};
    for (const auto& f : r.factors) {
      json fj = {{"note", f.note}};
      if (f.analysis) {
        fj = OneWayJson(f.analysis->original, f.analysis->alpha);
        fj["transform"] = TransformJson(f.analysis->transform, f.analysis->alpha);
      }
      j["by_" + f.factor] = fj;
    }
    j["two_way"] = r.two_way ? TwoWayJson(*r.two_way) : json({{"note", r.two_way_note}});
    responses[r.response] = j;
  }
  return {{"input", {{"study_h5", s.path}, {"trials", s.trials}, {"alpha", s.options.alpha}}},
          {"excluded", excluded},
          {"notes", s.notes},
          {"responses", responses}};
}

void WriteOneWayText(std::ostream& os, const stats::OneWayScaleResults& s, double alpha) {
  // Fisher's LSD groups as letters (groups sharing a letter do not differ; every group "a"
  // when the LSD did not run).
  std::vector<std::string> labels;
  std::vector<double> means;
  for (const auto& g : s.groups) {
    labels.push_back(g.label);
    means.push_back(g.mean);
  }
  std::vector<std::pair<std::string, std::string>> different;
  for (const auto& c : s.lsd)
    if (c.significant) different.emplace_back(c.group_a, c.group_b);
  const stats::LetterDisplay letters = stats::CompactLetters(labels, means, different);
  os << "  Groups (order of first appearance; LSD: groups sharing a letter do not differ)\n";
  os << "    " << std::left << std::setw(20) << "group" << std::right;
  Col(os, "n", 5);
  Col(os, "mean", 13);
  Col(os, "sd", 13);
  os << "  LSD\n";
  for (std::size_t i = 0; i < s.groups.size(); ++i) {
    const auto& g = s.groups[i];
    os << "    " << std::left << std::setw(20) << g.label << std::right;
    Col(os, g.n, 5);
    Col(os, format::Number(g.mean), 13);
    if (g.n > 1)
      Col(os, format::Number(g.sd), 13);
    else
      Col(os, format::kUndefined, 13);  // one observation has no s.d.
    os << "  " << letters.letters[i] << "\n";
  }
  const auto& a = s.anova;
  os << "  ANOVA\n";
  AnovaHeader(os);
  AnovaLine(os, "between", a.df_between, a.ss_between, a.ms_between, a.f, a.p);
  AnovaLine(os, "within", a.df_within, a.ss_within, a.ms_within, {}, {});
  AnovaLine(os, "total", a.df_total, a.ss_total, {}, {}, {});
  os << "    eta^2 = " << format::Number(a.eta_squared, format::Kind::kCoefficient) << "\n";
  os << "  Bartlett (equal variances): K^2 = "
     << format::Number(s.bartlett.k_squared, format::Kind::kStatistic) << ", df = " << s.bartlett.df
     << ", " << format::PValue(s.bartlett.p)
     << (s.bartlett.p < alpha ? "  -> rejected" : "  -> not rejected") << "\n";
  if (!s.bartlett.note.empty()) os << "    note: " << s.bartlett.note << "\n";
  if (s.welch) {
    os << "  Welch ANOVA: F = " << format::Number(s.welch->f, format::Kind::kStatistic)
       << ", df1 = " << format::Significant(s.welch->df1, 3)
       << ", df2 = " << format::Significant(s.welch->df2, 3) << ", " << format::PValue(s.welch->p)
       << "\n";
  } else {
    os << "  Welch ANOVA: " << s.welch_note << "\n";
  }
  if (!s.lsd_performed) {
    os << "  Fisher's LSD: " << s.lsd_note << "\n";
    return;
  }
  os << "  Fisher's LSD (" << 100.0 * (1.0 - alpha) << "% intervals, unadjusted p)\n";
  for (const auto& c : s.lsd)
    os << "    " << c.group_a << " - " << c.group_b << ": diff " << format::Number(c.difference)
       << ", se " << format::Number(c.standard_error, format::Kind::kError) << ", t(" << c.df
       << ") = " << format::Number(c.t, format::Kind::kStatistic) << ", " << format::PValue(c.p)
       << ", CI [" << format::Number(c.ci_low) << ", " << format::Number(c.ci_high) << "]"
       << (c.significant ? "  *" : "") << "\n";
}

void WriteTwoWayText(std::ostream& os, const stats::TwoWayAnovaResult& r) {
  os << "Two-way ANOVA (" << stats::ToString(r.type) << " sums of squares, "
     << (r.balanced ? "balanced" : "unbalanced") << ", " << r.levels_a.size() << " x "
     << r.levels_b.size() << " cells)\n";
  AnovaHeader(os);
  for (const auto* w : {&r.a, &r.b, &r.ab})
    AnovaLine(os, w->source, w->df, w->ss, w->ms, w->f, w->p);
  AnovaLine(os, "error", r.error.df, r.error.ss, r.error.ms, {}, {});
  AnovaLine(os, "total", r.df_total, r.ss_total, {}, {}, {});
}

void WriteOneWayAnalysisText(std::ostream& out, const std::string& response,
                             const std::string& factor, const std::string& source,
                             std::size_t observations, const stats::OneWayAnalysis& s,
                             const std::optional<stats::TwoWayAnovaResult>& two_way) {
  std::ostringstream os;
  os << std::setprecision(6);
  os << "One-way analysis of " << response << " by " << factor << " (" << source << ", "
     << observations << " observations, alpha = " << s.alpha << ")\n";
  WriteOneWayText(os, s.original, s.alpha);
  os << "Transform: " << s.transform.reason << "\n";
  if (s.transform.rerun) {
    os << "Rerun on " << s.transform.formula << "\n";
    WriteOneWayText(os, *s.transform.rerun, s.alpha);
  }
  if (two_way) WriteTwoWayText(os, *two_way);
  out << os.str();
}

void WriteStudyStatisticsText(std::ostream& out, const StudyStatistics& s) {
  std::ostringstream os;
  os << std::setprecision(6);
  os << "Study " << s.path << ": " << s.trials << " trial(s), alpha = " << s.options.alpha << "\n";
  for (const auto& [id, why] : s.excluded) os << "  excluded " << id << ": " << why << "\n";
  for (const auto& r : s.responses) {
    os << "\n== " << r.response << " (" << r.selection << ", n = " << r.values.size() << ")\n";
    if (r.values.empty()) continue;
    WriteCells(os, r);
    for (const auto& f : r.factors) {
      os << "\n" << r.response << " by " << f.factor << ": ";
      if (!f.analysis) {
        os << f.note << "\n";
        continue;
      }
      const auto& an = f.analysis->original.anova;
      os << "F(" << an.df_between << ", " << an.df_within
         << ") = " << format::Number(an.f, format::Kind::kStatistic) << ", " << format::PValue(an.p)
         << (an.p < s.options.alpha ? "  (significant)" : "") << "\n";
      WriteOneWayText(os, f.analysis->original, f.analysis->alpha);
      os << "  Transform: " << f.analysis->transform.reason << "\n";
      if (f.analysis->transform.rerun) {
        os << "  Rerun on " << f.analysis->transform.formula << "\n";
        WriteOneWayText(os, *f.analysis->transform.rerun, f.analysis->alpha);
      }
    }
    os << "\n";
    if (r.two_way)
      WriteTwoWayText(os, *r.two_way);
    else
      os << "Two-way ANOVA surface x angle: " << r.two_way_note << "\n";
  }
  out << os.str();
}

void WriteLongCsv(const std::string& path, const stats::OneWayAnalysis& s,
                  const std::optional<stats::TwoWayAnovaResult>& two_way) {
  io::WriteFileAtomically(path, [&](std::ostream& out) {
    LongCsv csv(out);
    CsvScale(csv, "", s.original);
    if (s.transform.box_cox) {
      const auto& b = *s.transform.box_cox;
      csv.Add("transform", "box_cox", "lambda_ml", b.lambda_ml);
      csv.Add("transform", "box_cox", "ci_low", b.ci_low);
      csv.Add("transform", "box_cox", "ci_high", b.ci_high);
      csv.Add("transform", "box_cox", "lambda", b.lambda);
      csv.Add("transform", "box_cox", "shift", b.shift);
      csv.Add("transform", "box_cox", "applied", s.transform.applied ? 1.0 : 0.0);
    }
    if (s.transform.rerun) CsvScale(csv, "transformed_", *s.transform.rerun);
    if (two_way) {
      for (const auto* w : {&two_way->a, &two_way->b, &two_way->ab, &two_way->error}) {
        csv.Add("two_way", w->source, "df", static_cast<double>(w->df));
        csv.Add("two_way", w->source, "ss", w->ss);
        csv.Add("two_way", w->source, "ms", w->ms);
        if (w != &two_way->error) {
          csv.Add("two_way", w->source, "f", w->f);
          csv.Add("two_way", w->source, "p", w->p);
        }
      }
      csv.Add("two_way", "total", "df", static_cast<double>(two_way->df_total));
      csv.Add("two_way", "total", "ss", two_way->ss_total);
    }
  });
}

}  // namespace hoof::study
