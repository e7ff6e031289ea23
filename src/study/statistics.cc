#include "study/statistics.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/frames.h"
#include "io/atomic_file.h"
#include "io/csv.h"
#include "stats/grouping.h"
#include "studyfile/stats_tables.h"

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

/// The table `name` of `rows`, each row's columns declared by its Serialize (stats_tables.h).
template <class Row>
Table Rows(std::string name, std::string description, const std::vector<Row>& rows,
           const Row& declared = Row{}) {
  return studyfile::TableWriter::Of(
      std::move(name), std::move(description), rows,
      [](auto& a, const auto& row) { studyfile::Serialize(a, row); }, declared);
}

void ScaleTables(const std::string& prefix, const stats::OneWayScaleResults& s,
                 std::vector<Table>& out) {
  std::vector<studyfile::GroupRow> groups;
  // The s.d. of one observation is undefined: NaN in the file, as n/a on the page and in text.
  for (const auto& g : s.groups)
    groups.push_back({g.label, g.n, g.mean, g.n > 1 ? g.sd : core::kNaN});
  out.push_back(Rows(prefix + "groups", "group summaries, order of first appearance", groups));
  const auto& a = s.anova;
  const double nan = core::kNaN;
  out.push_back(Rows<studyfile::AnovaRow>(
      prefix + "anova", "one-way ANOVA table",
      {{"between", a.df_between, a.ss_between, a.ms_between, a.f, a.p, a.eta_squared},
       {"within", a.df_within, a.ss_within, a.ms_within, nan, nan, nan},
       {"total", a.df_total, a.ss_total, nan, nan, nan, nan}}));
  const auto& b = s.bartlett;
  const auto& w = s.welch;
  out.push_back(Rows<studyfile::VarianceTestRow>(
      prefix + "tests", "Bartlett (K^2, chi-squared df1) and Welch (F, df1, df2)",
      {{"bartlett", b.k_squared, static_cast<double>(b.df), nan, b.p, b.note},
       {"welch", w ? w->f : nan, w ? w->df1 : nan, w ? w->df2 : nan, w ? w->p : nan,
        s.welch_note}}));
  std::vector<studyfile::LsdRow> lsd;
  for (const auto& c : s.lsd)
    lsd.push_back({c.group_a + " - " + c.group_b, c.group_a, c.group_b, c.difference,
                   c.standard_error, c.t, c.df, c.p, c.ci_low, c.ci_high, c.significant});
  out.push_back(Rows(prefix + "lsd",
                     s.lsd_performed ? "Fisher's LSD pairs (unadjusted)"
                                     : "Fisher's LSD not performed: " + s.lsd_note,
                     lsd));
}

void FactorTables(const std::string& prefix, const stats::OneWayAnalysis& an,
                  std::vector<Table>& out) {
  ScaleTables(prefix, an.original, out);
  const auto& t = an.transform;
  const double nan = core::kNaN;
  studyfile::TransformRow row{t.reason, t.considered, t.applied, t.formula, nan,
                              nan,      nan,          nan,       nan};
  if (t.box_cox) {
    const auto& bc = *t.box_cox;
    row.lambda_ml = bc.lambda_ml;
    row.lambda = bc.lambda;
    row.shift = bc.shift;
    row.ci_low = bc.ci_low;
    row.ci_high = bc.ci_high;
  }
  out.push_back(Rows<studyfile::TransformRow>(
      prefix + "transform", "variance-stabilizing transform decision (Box-Cox)", {row}));
  if (t.rerun) ScaleTables(prefix + "transformed/", *t.rerun, out);
}

}  // namespace

std::vector<Table> StatisticsTables(const StudyStatistics& s) {
  std::vector<Table> out;
  std::vector<studyfile::ExcludedRow> excluded;
  for (const auto& [id, why] : s.excluded) excluded.push_back({id, why});
  out.push_back(Rows("excluded", "trials left out of every analysis", excluded));
  for (const auto& r : s.responses) {
    std::vector<studyfile::CellRow> cells;
    for (const auto& c : r.cells) {
      const auto bar = c.label.find('|');
      cells.push_back({r.response, c.label, c.label.substr(0, bar), c.label.substr(bar + 1), c.n,
                       c.mean, c.n > 1 ? c.sd : core::kNaN});
    }
    studyfile::CellRow declared;
    declared.response = r.response;
    out.push_back(Rows(studyfile::StatsTableName(r.response, "cells"),
                       r.response + ": mean (s.d., n) per surface x angle, " + r.selection, cells,
                       declared));
    for (const auto& f : r.factors)
      if (f.analysis) FactorTables(studyfile::FactorPrefix(r.response, f.factor), *f.analysis, out);
    if (r.two_way) {
      const auto& w = *r.two_way;
      std::vector<studyfile::TwoWayRow> rows;
      for (const auto* row : {&w.a, &w.b, &w.ab, &w.error})
        rows.push_back({row->source, row->df, row->ss, row->ms, row->f, row->p});
      out.push_back(Rows(studyfile::StatsTableName(r.response, "two_way"),
                         stats::ToString(w.type) + " two-way ANOVA, surface x angle", rows));
    }
    std::vector<studyfile::NoteRow> notes;
    for (const auto& f : r.factors)
      if (!f.analysis) notes.push_back({"by_" + f.factor, f.note});
    if (!r.two_way) notes.push_back({"two_way", r.two_way_note});
    out.push_back(Rows(studyfile::StatsTableName(r.response, "notes"),
                       "analyses not computed and why", notes));
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
