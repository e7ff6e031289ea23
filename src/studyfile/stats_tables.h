#pragma once
/// @file
/// The study file's `/stats` group: its tables, each a row type whose columns are declared once
/// (a Serialize() visited by TableWriter in hoof::study, which computes the statistics, and by
/// TableReader here), where each table lives, and the typed reader the report uses
/// (docs/hdf5-schema.md, "/stats").
///
/// Counts, degrees of freedom and flags are stored as floating-point columns, as they were
/// before the tables had a schema: StoredAsNumber keeps that, so older files read and the file
/// `run` writes is unchanged.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "studyfile/table_archive.h"

namespace hoof::studyfile {

/// A trial left out of every analysis.
struct ExcludedRow {
  std::string id;
  std::string reason;
};

/// One surface x angle cell of a response: mean (s.d., n).
struct CellRow {
  std::string response;  ///< not stored: names the response in the mean's column description
  std::string cell;      ///< "surface|angle"
  std::string surface;
  std::string angle_deg;  ///< as a label ("20")
  std::size_t n = 0;
  double mean = 0, sd = 0;
};

/// One group of a one-way analysis.
struct GroupRow {
  std::string group;
  std::size_t n = 0;
  double mean = 0, sd = 0;
};

/// One line of a one-way ANOVA table: between, within or total.
struct AnovaRow {
  std::string source;
  std::size_t df = 0;
  double ss = 0, ms = 0, f = 0, p = 0, eta_squared = 0;  ///< NaN where the line has none
};

/// Bartlett's test of equal variances or Welch's ANOVA.
struct VarianceTestRow {
  std::string test;  ///< "bartlett" or "welch"
  double statistic = 0, df1 = 0, df2 = 0, p = 0;
  std::string note;
};

/// One pair of Fisher's LSD.
struct LsdRow {
  std::string pair;  ///< "a - b"
  std::string a, b;
  double difference = 0, standard_error = 0, t = 0;
  std::size_t df = 0;
  double p = 0, ci_low = 0, ci_high = 0;
  bool significant = false;
};

/// The variance-stabilising transform decision (Box-Cox).
struct TransformRow {
  std::string decision;
  bool considered = false, applied = false;
  std::string formula;
  double lambda_ml = 0, lambda = 0, shift = 0, ci_low = 0, ci_high = 0;  ///< NaN when none
};

/// One effect of the two-way ANOVA, surface x angle.
struct TwoWayRow {
  std::string source;
  std::size_t df = 0;
  double ss = 0, ms = 0, f = 0, p = 0;
};

/// An analysis not computed, and why.
struct NoteRow {
  std::string analysis;  ///< "by_speed", "two_way"
  std::string note;
};

/// A count, degrees of freedom or flag in a floating-point column (see the file comment).
template <class Archive, class T>
void StoredAsNumber(Archive& a, const std::string& name, T& v, const std::string& units,
                    const std::string& description) {
  if constexpr (Archive::kWriting) {
    a.Number(name, static_cast<double>(v), units, description);
  } else {
    double x = 0;
    a.Number(name, x, units, description);
    v = static_cast<std::remove_const_t<T>>(x);
  }
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, ExcludedRow>
void Serialize(A& a, T& r) {
  a.Text("id", r.id, "trial id");
  a.Text("reason", r.reason, "why");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, CellRow>
void Serialize(A& a, T& r) {
  a.Text("cell", r.cell, "surface|angle");
  a.Text("surface", r.surface, "surface");
  a.Text("angle_deg", r.angle_deg, "surface angle (deg), as a label");
  StoredAsNumber(a, "n", r.n, "1", "observations");
  a.Number("mean", r.mean, "1", "mean of " + r.response);
  a.Number("sd", r.sd, "1", "sample standard deviation (NaN for one observation)");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, GroupRow>
void Serialize(A& a, T& r) {
  a.Text("group", r.group, "group label");
  StoredAsNumber(a, "n", r.n, "1", "observations");
  a.Number("mean", r.mean, "1", "group mean (units of the response)");
  a.Number("sd", r.sd, "1", "sample standard deviation (NaN for one observation)");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, AnovaRow>
void Serialize(A& a, T& r) {
  a.Text("source", r.source, "between, within or total");
  StoredAsNumber(a, "df", r.df, "1", "degrees of freedom");
  a.Number("ss", r.ss, "1", "sum of squares");
  a.Number("ms", r.ms, "1", "mean square");
  a.Number("f", r.f, "1", "F statistic");
  a.Number("p", r.p, "1", "P(F >= f)");
  a.Number("eta_squared", r.eta_squared, "1", "SS_between / SS_total");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, VarianceTestRow>
void Serialize(A& a, T& r) {
  a.Text("test", r.test, "bartlett or welch");
  a.Number("statistic", r.statistic, "1", "K^2 or Welch's F");
  a.Number("df1", r.df1, "1", "degrees of freedom");
  a.Number("df2", r.df2, "1", "denominator degrees of freedom (Welch)");
  a.Number("p", r.p, "1", "p-value");
  a.Text("note", r.note, "why a result is a limit or absent");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, LsdRow>
void Serialize(A& a, T& r) {
  a.Text("pair", r.pair, "a - b");
  a.Text("a", r.a, "group a");
  a.Text("b", r.b, "group b");
  a.Number("difference", r.difference, "1", "mean(a) - mean(b)");
  a.Number("standard_error", r.standard_error, "1", "of the difference");
  a.Number("t", r.t, "1", "t statistic");
  StoredAsNumber(a, "df", r.df, "1", "degrees of freedom");
  a.Number("p", r.p, "1", "two-sided p, unadjusted");
  a.Number("ci_low", r.ci_low, "1", "lower end of the interval");
  a.Number("ci_high", r.ci_high, "1", "upper end of the interval");
  StoredAsNumber(a, "significant", r.significant, "1", "1 when p < alpha");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, TransformRow>
void Serialize(A& a, T& r) {
  a.Text("decision", r.decision, "the decision in words");
  StoredAsNumber(a, "considered", r.considered, "1", "1 when Bartlett rejected");
  StoredAsNumber(a, "applied", r.applied, "1", "1 when the data were transformed");
  a.Text("formula", r.formula, "the transform");
  a.Number("lambda_ml", r.lambda_ml, "1", "maximum-likelihood lambda");
  a.Number("lambda", r.lambda, "1", "lambda used");
  a.Number("shift", r.shift, "1", "shift added before transforming");
  a.Number("ci_low", r.ci_low, "1", "profile-likelihood interval of lambda");
  a.Number("ci_high", r.ci_high, "1", "profile-likelihood interval of lambda");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, TwoWayRow>
void Serialize(A& a, T& r) {
  a.Text("source", r.source, "effect");
  StoredAsNumber(a, "df", r.df, "1", "degrees of freedom");
  a.Number("ss", r.ss, "1", "sum of squares");
  a.Number("ms", r.ms, "1", "mean square");
  a.Number("f", r.f, "1", "F statistic");
  a.Number("p", r.p, "1", "P(F >= f)");
}

template <class A, class T>
requires std::is_same_v<std::remove_const_t<T>, NoteRow>
void Serialize(A& a, T& r) {
  a.Text("analysis", r.analysis, "which");
  a.Text("note", r.note, "why");
}

/// Rows and the description their table is stored with.
template <class Row>
struct StoredTable {
  std::string description;
  std::vector<Row> rows;
};

/// One scale of a one-way analysis (the data as measured, or transformed).
struct StoredScale {
  StoredTable<GroupRow> groups;
  StoredTable<AnovaRow> anova;
  StoredTable<VarianceTestRow> tests;
  StoredTable<LsdRow> lsd;  ///< its description says why, when LSD was not performed
};

/// The one-way analysis of a response by one factor.
struct StoredFactor {
  std::string factor;  ///< "surface", "angle", "speed"
  StoredScale original;
  TransformRow transform;
  std::optional<StoredScale> transformed;  ///< when the transform was applied
};

/// Everything stored for one response.
struct StoredResponse {
  std::string response;  ///< "e" or "mu_eff"
  StoredTable<CellRow> cells;
  std::vector<StoredFactor> factors;  ///< those computed, in the order surface, angle, speed
  std::optional<StoredTable<TwoWayRow>> two_way;
  std::vector<NoteRow> notes;  ///< the analyses not computed
};

/// The whole `/stats` group.
struct StoredStatistics {
  std::string description;  ///< the group's: the options the statistics ran with
  std::vector<ExcludedRow> excluded;
  std::vector<StoredResponse> responses;  ///< e, then mu_eff, where stored
};

/// The responses and factors /stats may hold, in their order.
inline constexpr const char* kStatsResponses[] = {"e", "mu_eff"};
inline constexpr const char* kStatsFactors[] = {"surface", "angle", "speed"};

/// Table names (relative to /stats, as WriteTables takes them).
inline std::string StatsTableName(const std::string& response, const std::string& table) {
  return response + "/" + table;
}
/// The prefix of a factor's tables: "e/by_surface/" (and "e/by_surface/transformed/").
inline std::string FactorPrefix(const std::string& response, const std::string& factor,
                                bool transformed = false) {
  return response + "/by_" + factor + "/" + (transformed ? "transformed/" : "");
}

/// Whether `h5` holds a /stats group.
bool HasStatistics(const std::filesystem::path& h5);

/// Reads /stats back. Throws std::runtime_error naming the file and the table when a table that
/// must be there is missing or a column is wrong; a study file without /stats is an error too
/// (check HasStatistics first).
StoredStatistics ReadStatistics(const std::filesystem::path& h5);

}  // namespace hoof::studyfile
