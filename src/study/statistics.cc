#include "study/statistics.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/frames.h"
#include "io/atomic_file.h"
#include "io/csv.h"
#include "stats/grouping.h"

namespace hoof::study {

using studyfile::Column;
using studyfile::Table;

namespace {

/// A factor's label for a number: "20", "3.17" (shortest form that reads back as `value`).
std::string Label(double value) {
  std::ostringstream os;
  os << std::setprecision(15) << value;
  return os.str();
}

ResponseAnalysis AnalyzeResponse(const std::vector<studyfile::TrialResult>& ok,
                                 const std::string& response, const StatisticsOptions& a) {
  ResponseAnalysis out;
  out.response = response;
  const bool mu = response == "mu_eff";
  out.selection =
      mu ? "successful oblique trials (angle > 0), as in the paper" : "successful trials";
  bool all_speeds = true;
  for (const auto& t : ok) {
    const double v = mu ? t.mu_eff : t.e;
    if ((mu && !(t.surface_angle_deg > 0)) || !std::isfinite(v)) continue;
    out.values.push_back(v);
    out.surface.push_back(t.surface);
    out.angle.push_back(Label(t.surface_angle_deg));
    all_speeds = all_speeds && std::isfinite(t.nominal_speed_m_s);
    out.speed.push_back(std::isfinite(t.nominal_speed_m_s) ? Label(t.nominal_speed_m_s) : "");
  }
  if (out.values.empty()) return out;
  std::vector<std::string> cell;
  for (std::size_t i = 0; i < out.values.size(); ++i)
    cell.push_back(out.surface[i] + "|" + out.angle[i]);
  out.cells = stats::Summarize(stats::GroupByLabel(out.values, cell));
  stats::OneWayAnalysisOptions options;
  options.alpha = a.alpha;
  const std::pair<const char*, const std::vector<std::string>*> factors[] = {
      {"surface", &out.surface}, {"angle", &out.angle}, {"speed", &out.speed}};
  for (const auto& [name, labels] : factors) {
    FactorAnalysis f{name, std::nullopt, ""};
    if (labels == &out.speed && !all_speeds) {
      f.note = "not computed: some trials have no nominal_speed_m_s in trial.json";
    } else {
      try {
        f.analysis = stats::AnalyzeOneWay(stats::GroupByLabel(out.values, *labels), options);
      } catch (const std::invalid_argument& e) {
        f.note = std::string("not computed: ") + e.what();
      }
    }
    out.factors.push_back(std::move(f));
  }
  try {
    stats::TwoWayOptions o;
    o.type = a.ss_type;
    o.name_a = "surface";
    o.name_b = "angle";
    out.two_way = stats::TwoWayAnova(out.values, out.surface, out.angle, o);
  } catch (const std::invalid_argument& e) {
    out.two_way_note = std::string("not computed: ") + e.what();
  }
  return out;
}

}  // namespace

StudyStatistics AnalyzeStatistics(const studyfile::StudyResults& study, const StatisticsOptions& a,
                                  const std::string& path) {
  StudyStatistics s;
  s.path = path;
  s.options = a;
  s.trials = study.trials.size();
  std::vector<studyfile::TrialResult> ok;
  for (const auto& t : study.trials) {
    if (t.success && std::isfinite(t.e))
      ok.push_back(t);
    else
      s.excluded.emplace_back(t.id, t.success ? "e was not measured" : t.error);
  }
  if (ok.empty())
    throw std::runtime_error(path + ": none of the " + std::to_string(s.trials) +
                             " trials succeeded; nothing to analyse");
  if (!s.excluded.empty())
    s.notes.push_back(std::to_string(s.excluded.size()) + " failed trial(s) excluded");
  for (const char* r : {"e", "mu_eff"}) s.responses.push_back(AnalyzeResponse(ok, r, a));
  return s;
}

// Tables (for /stats in the study file and for --out-csv) --------------------------------

namespace {

std::vector<double> Sizes(const std::vector<stats::GroupSummary>& g) {
  std::vector<double> n;
  for (const auto& x : g) n.push_back(static_cast<double>(x.n));
  return n;
}

void ScaleTables(const std::string& prefix, const stats::OneWayScaleResults& s,
                 std::vector<Table>& out) {
  std::vector<std::string> labels;
  std::vector<double> mean, sd;
  for (const auto& g : s.groups) {
    labels.push_back(g.label);
    mean.push_back(g.mean);
    sd.push_back(g.sd);
  }
  out.push_back({prefix + "groups",
                 "group summaries, order of first appearance",
                 {Column::Texts("group", "group label", labels),
                  Column::Numbers("n", "1", "observations", Sizes(s.groups)),
                  Column::Numbers("mean", "1", "group mean (units of the response)", mean),
                  Column::Numbers("sd", "1", "sample standard deviation", sd)}});
  const auto& a = s.anova;
  const double nan = core::kNaN;
  out.push_back(
      {prefix + "anova",
       "one-way ANOVA table",
       {Column::Texts("source", "between, within or total", {"between", "within", "total"}),
        Column::Numbers("df", "1", "degrees of freedom",
                        {static_cast<double>(a.df_between), static_cast<double>(a.df_within),
                         static_cast<double>(a.df_total)}),
        Column::Numbers("ss", "1", "sum of squares", {a.ss_between, a.ss_within, a.ss_total}),
        Column::Numbers("ms", "1", "mean square", {a.ms_between, a.ms_within, nan}),
        Column::Numbers("f", "1", "F statistic", {a.f, nan, nan}),
        Column::Numbers("p", "1", "P(F >= f)", {a.p, nan, nan}),
        Column::Numbers("eta_squared", "1", "SS_between / SS_total", {a.eta_squared, nan, nan})}});
  const auto& b = s.bartlett;
  std::vector<std::string> test = {"bartlett"}, note = {b.note};
  std::vector<double> stat = {b.k_squared}, df1 = {static_cast<double>(b.df)}, df2 = {nan},
                      p = {b.p};
  test.push_back("welch");
  stat.push_back(s.welch ? s.welch->f : nan);
  df1.push_back(s.welch ? s.welch->df1 : nan);
  df2.push_back(s.welch ? s.welch->df2 : nan);
  p.push_back(s.welch ? s.welch->p : nan);
  note.push_back(s.welch_note);
  out.push_back({prefix + "tests",
                 "Bartlett (K^2, chi-squared df1) and Welch (F, df1, df2)",
                 {Column::Texts("test", "bartlett or welch", test),
                  Column::Numbers("statistic", "1", "K^2 or Welch's F", stat),
                  Column::Numbers("df1", "1", "degrees of freedom", df1),
                  Column::Numbers("df2", "1", "denominator degrees of freedom (Welch)", df2),
                  Column::Numbers("p", "1", "p-value", p),
                  Column::Texts("note", "why a result is a limit or absent", note)}});
  std::vector<std::string> pa, pb;
  std::vector<double> d, se, t, df, pp, lo, hi, sig;
  for (const auto& c : s.lsd) {
    pa.push_back(c.group_a);
    pb.push_back(c.group_b);
    d.push_back(c.difference);
    se.push_back(c.standard_error);
    t.push_back(c.t);
    df.push_back(static_cast<double>(c.df));
    pp.push_back(c.p);
    lo.push_back(c.ci_low);
    hi.push_back(c.ci_high);
    sig.push_back(c.significant ? 1.0 : 0.0);
  }
  std::vector<std::string> pair;
  for (std::size_t i = 0; i < pa.size(); ++i) pair.push_back(pa[i] + " - " + pb[i]);
  out.push_back({prefix + "lsd",
                 s.lsd_performed ? "Fisher's LSD pairs (unadjusted)"
                                 : "Fisher's LSD not performed: " + s.lsd_note,
                 {Column::Texts("pair", "a - b", pair), Column::Texts("a", "group a", pa),
                  Column::Texts("b", "group b", pb),
                  Column::Numbers("difference", "1", "mean(a) - mean(b)", d),
                  Column::Numbers("standard_error", "1", "of the difference", se),
                  Column::Numbers("t", "1", "t statistic", t),
                  Column::Numbers("df", "1", "degrees of freedom", df),
                  Column::Numbers("p", "1", "two-sided p, unadjusted", pp),
                  Column::Numbers("ci_low", "1", "lower end of the interval", lo),
                  Column::Numbers("ci_high", "1", "upper end of the interval", hi),
                  Column::Numbers("significant", "1", "1 when p < alpha", sig)}});
}

void FactorTables(const std::string& prefix, const stats::OneWayAnalysis& an,
                  std::vector<Table>& out) {
  ScaleTables(prefix, an.original, out);
  const auto& t = an.transform;
  const double nan = core::kNaN;
  const auto bc = [&](double stats::BoxCoxResult::*field) {
    return std::vector<double>{t.box_cox ? (*t.box_cox).*field : nan};
  };
  out.push_back(
      {prefix + "transform",
       "variance-stabilizing transform decision (Box-Cox)",
       {Column::Texts("decision", "the decision in words", {t.reason}),
        Column::Numbers("considered", "1", "1 when Bartlett rejected", {t.considered ? 1.0 : 0.0}),
        Column::Numbers("applied", "1", "1 when the data were transformed",
                        {t.applied ? 1.0 : 0.0}),
        Column::Texts("formula", "the transform", {t.formula}),
        Column::Numbers("lambda_ml", "1", "maximum-likelihood lambda",
                        bc(&stats::BoxCoxResult::lambda_ml)),
        Column::Numbers("lambda", "1", "lambda used", bc(&stats::BoxCoxResult::lambda)),
        Column::Numbers("shift", "1", "shift added before transforming",
                        bc(&stats::BoxCoxResult::shift)),
        Column::Numbers("ci_low", "1", "profile-likelihood interval of lambda",
                        bc(&stats::BoxCoxResult::ci_low)),
        Column::Numbers("ci_high", "1", "profile-likelihood interval of lambda",
                        bc(&stats::BoxCoxResult::ci_high))}});
  if (t.rerun) ScaleTables(prefix + "transformed/", *t.rerun, out);
}

}  // namespace

std::vector<Table> StatisticsTables(const StudyStatistics& s) {
  std::vector<Table> out;
  std::vector<std::string> ids, reasons;
  for (const auto& [id, why] : s.excluded) {
    ids.push_back(id);
    reasons.push_back(why);
  }
  out.push_back({"excluded",
                 "trials left out of every analysis",
                 {Column::Texts("id", "trial id", ids), Column::Texts("reason", "why", reasons)}});
  for (const auto& r : s.responses) {
    std::vector<std::string> surface, angle;
    std::vector<double> mean, sd;
    for (const auto& c : r.cells) {
      const auto bar = c.label.find('|');
      surface.push_back(c.label.substr(0, bar));
      angle.push_back(c.label.substr(bar + 1));
      mean.push_back(c.mean);
      sd.push_back(c.sd);
    }
    out.push_back({r.response + "/cells",
                   r.response + ": mean (s.d., n) per surface x angle, " + r.selection,
                   {Column::Texts("cell", "surface|angle",
                                  [&] {
                                    std::vector<std::string> v;
                                    for (const auto& c : r.cells) v.push_back(c.label);
                                    return v;
                                  }()),
                    Column::Texts("surface", "surface", surface),
                    Column::Texts("angle_deg", "surface angle (deg), as a label", angle),
                    Column::Numbers("n", "1", "observations", Sizes(r.cells)),
                    Column::Numbers("mean", "1", "mean of " + r.response, mean),
                    Column::Numbers("sd", "1", "sample standard deviation", sd)}});
    for (const auto& f : r.factors)
      if (f.analysis) FactorTables(r.response + "/by_" + f.factor + "/", *f.analysis, out);
    if (r.two_way) {
      const auto& w = *r.two_way;
      std::vector<std::string> src;
      std::vector<double> df, ss, ms, fv, p;
      for (const auto* row : {&w.a, &w.b, &w.ab, &w.error}) {
        src.push_back(row->source);
        df.push_back(static_cast<double>(row->df));
        ss.push_back(row->ss);
        ms.push_back(row->ms);
        fv.push_back(row->f);
        p.push_back(row->p);
      }
      out.push_back({r.response + "/two_way",
                     stats::ToString(w.type) + " two-way ANOVA, surface x angle",
                     {Column::Texts("source", "effect", src),
                      Column::Numbers("df", "1", "degrees of freedom", df),
                      Column::Numbers("ss", "1", "sum of squares", ss),
                      Column::Numbers("ms", "1", "mean square", ms),
                      Column::Numbers("f", "1", "F statistic", fv),
                      Column::Numbers("p", "1", "P(F >= f)", p)}});
    }
    std::vector<std::string> what, note;
    for (const auto& f : r.factors)
      if (!f.analysis) {
        what.push_back("by_" + f.factor);
        note.push_back(f.note);
      }
    if (!r.two_way) {
      what.push_back("two_way");
      note.push_back(r.two_way_note);
    }
    out.push_back({r.response + "/notes",
                   "analyses not computed and why",
                   {Column::Texts("analysis", "which", what), Column::Texts("note", "why", note)}});
  }
  return out;
}

/// The tables as one long CSV (table,row,statistic,value): the row is the table's first
/// column, every other column one statistic; text values are quoted.
void WriteTablesCsv(const std::string& path, const std::vector<Table>& tables) {
  io::WriteFileAtomically(path, [&](std::ostream& out) {
    out << "table,row,statistic,value\n";
    for (const Table& t : tables) {
      if (t.columns.empty()) continue;
      const auto* labels = std::get_if<std::vector<std::string>>(&t.columns[0].values);
      for (std::size_t r = 0; r < t.columns[0].size(); ++r)
        for (std::size_t c = labels ? 1 : 0; c < t.columns.size(); ++c) {
          out << io::CsvEscape(t.name) << ","
              << io::CsvEscape(labels ? (*labels)[r] : std::to_string(r)) << ","
              << io::CsvEscape(t.columns[c].name) << "," << t.columns[c].CsvCell(r) << "\n";
        }
    }
  });
}

std::string StatisticsDescription(const StatisticsOptions& options) {
  return "hoofimpact stats: e and mu_eff by surface, angle and speed (alpha " +
         Label(options.alpha) + ", two-way " +
         (options.ss_type == stats::SumOfSquaresType::kTypeI ? "I" : "III") + ")";
}

StudyStatistics StoreStatistics(const std::filesystem::path& study_h5,
                                const StatisticsOptions& options,
                                const std::filesystem::path& out_csv, const std::string& shown_as) {
  const std::string path = shown_as.empty() ? study_h5.string() : shown_as;
  StudyStatistics s = AnalyzeStatistics(studyfile::ReadStudyResults(study_h5), options, path);
  const std::vector<Table> tables = StatisticsTables(s);
  studyfile::WriteTables(study_h5, "/stats", StatisticsDescription(options), tables);
  if (!out_csv.empty()) WriteTablesCsv(out_csv, tables);
  return s;
}

}  // namespace hoof::study
