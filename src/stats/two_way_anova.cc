#include "stats/two_way_anova.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <utility>

#include <Eigen/Dense>

#include "stats/accurate_sum.h"
#include "stats/distributions.h"
#include "stats/grouping.h"
#include "stats/moments.h"

namespace hoof::stats {
namespace {

using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using VectorL = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

/// Level index of every observation, levels in order of first appearance.
std::vector<std::size_t> Index(const std::vector<std::string>& labels, const std::string& name,
                               std::vector<std::string>& levels) {
  std::unordered_map<std::string, std::size_t> index;
  std::vector<std::size_t> out;
  out.reserve(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i].empty()) {
      std::ostringstream os;
      os << "observation " << i << " has an empty " << name << " label";
      throw std::invalid_argument(os.str());
    }
    auto [it, inserted] = index.try_emplace(labels[i], levels.size());
    if (inserted) levels.push_back(labels[i]);
    out.push_back(it->second);
  }
  if (levels.size() < 2) {
    throw std::invalid_argument("factor " + name + " has only 1 level (\"" + levels.at(0) +
                                "\"); two-way ANOVA needs at least 2 levels of each factor");
  }
  return out;
}

/// (L m)' (L D^-1 L')^-1 (L m): the sum of squares of the hypothesis L mu = 0.
long double HypothesisSS(const MatrixL& l, const VectorL& means, const VectorL& inverse_n) {
  const VectorL v = l * means;
  const MatrixL c = l * inverse_n.asDiagonal() * l.transpose();
  const VectorL x = c.ldlt().solve(v);
  const long double ss = v.dot(x);
  return ss > 0.0L ? ss : 0.0L;
}

/// Contrast matrices of the Type III hypotheses, over cells ordered i * b + j.
MatrixL ContrastA(std::size_t a, std::size_t b) {
  MatrixL l = MatrixL::Zero(static_cast<Eigen::Index>(a - 1), static_cast<Eigen::Index>(a * b));
  for (std::size_t r = 0; r + 1 < a; ++r)
    for (std::size_t j = 0; j < b; ++j) {
      l(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(r * b + j)) = 1.0L / b;
      l(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>((a - 1) * b + j)) = -1.0L / b;
    }
  return l;
}

MatrixL ContrastB(std::size_t a, std::size_t b) {
  MatrixL l = MatrixL::Zero(static_cast<Eigen::Index>(b - 1), static_cast<Eigen::Index>(a * b));
  for (std::size_t s = 0; s + 1 < b; ++s)
    for (std::size_t i = 0; i < a; ++i) {
      l(static_cast<Eigen::Index>(s), static_cast<Eigen::Index>(i * b + s)) = 1.0L / a;
      l(static_cast<Eigen::Index>(s), static_cast<Eigen::Index>(i * b + b - 1)) = -1.0L / a;
    }
  return l;
}

MatrixL ContrastAB(std::size_t a, std::size_t b) {
  MatrixL l =
      MatrixL::Zero(static_cast<Eigen::Index>((a - 1) * (b - 1)), static_cast<Eigen::Index>(a * b));
  for (std::size_t r = 0; r + 1 < a; ++r)
    for (std::size_t s = 0; s + 1 < b; ++s) {
      const auto row = static_cast<Eigen::Index>(r * (b - 1) + s);
      l(row, static_cast<Eigen::Index>(r * b + s)) += 1.0L;
      l(row, static_cast<Eigen::Index>(r * b + b - 1)) -= 1.0L;
      l(row, static_cast<Eigen::Index>((a - 1) * b + s)) -= 1.0L;
      l(row, static_cast<Eigen::Index>((a - 1) * b + b - 1)) += 1.0L;
    }
  return l;
}

TwoWayRow MakeRow(std::string source, std::size_t df, long double ss, long double mse,
                  std::size_t df_error) {
  TwoWayRow row;
  row.source = std::move(source);
  row.df = df;
  row.ss = static_cast<double>(ss);
  const long double ms = ss / static_cast<long double>(df);
  row.ms = static_cast<double>(ms);
  row.f = static_cast<double>(ms / mse);
  row.p = FUpperTail(row.f, static_cast<double>(df), static_cast<double>(df_error));
  return row;
}

/// Groups the observations by cell (i * b + j) and checks that every cell is filled.
GroupedData Cells(const std::vector<double>& response, const std::vector<std::size_t>& ia,
                  const std::vector<std::size_t>& ib, const TwoWayOptions& o,
                  const std::vector<std::string>& la, const std::vector<std::string>& lb) {
  const std::size_t a = la.size(), b = lb.size();
  GroupedData cells;
  cells.values.resize(a * b);
  for (std::size_t i = 0; i < a; ++i)
    for (std::size_t j = 0; j < b; ++j) cells.labels.push_back(la[i] + ":" + lb[j]);
  for (std::size_t r = 0; r < response.size(); ++r) {
    if (!std::isfinite(response[r])) {
      std::ostringstream os;
      os << "observation " << r << " (" << o.name_a << " = \"" << la[ia[r]] << "\", " << o.name_b
         << " = \"" << lb[ib[r]] << "\") is " << (std::isnan(response[r]) ? "NaN" : "infinite")
         << "; every response value must be finite";
      throw std::invalid_argument(os.str());
    }
    cells.values[ia[r] * b + ib[r]].push_back(response[r]);
  }
  for (std::size_t i = 0; i < a; ++i)
    for (std::size_t j = 0; j < b; ++j)
      if (cells.values[i * b + j].empty()) {
        throw std::invalid_argument("cell " + o.name_a + " = \"" + la[i] + "\", " + o.name_b +
                                    " = \"" + lb[j] +
                                    "\" has no observations; this two-way ANOVA needs every "
                                    "cell filled");
      }
  return cells;
}

}  // namespace

std::string ToString(SumOfSquaresType type) {
  return type == SumOfSquaresType::kTypeI ? "Type I" : "Type III";
}

namespace {

/// Throws std::invalid_argument unless the response and both factors pair one to one.
void CheckPairing(const std::vector<double>& response, const std::vector<std::string>& factor_a,
                  const std::vector<std::string>& factor_b, const TwoWayOptions& options) {
  if (response.size() != factor_a.size() || response.size() != factor_b.size()) {
    std::ostringstream os;
    os << "response has " << response.size() << " values, " << options.name_a << " has "
       << factor_a.size() << " labels and " << options.name_b << " has " << factor_b.size()
       << "; they must pair one to one";
    throw std::invalid_argument(os.str());
  }
}

/// Type I (sequential) sums of squares of A and then B given A, from the cell moments `m` of
/// an a x b design and the interaction's `ss_ab`.
std::pair<long double, long double> TypeISums(const Moments& m, std::size_t a, std::size_t b,
                                              long double ss_ab) {
  AccurateSum sa, within_rows;
  for (std::size_t i = 0; i < a; ++i) {
    AccurateSum row_sum;
    std::size_t row_n = 0;
    for (std::size_t j = 0; j < b; ++j) {
      row_sum.Add(static_cast<long double>(m.groups[i * b + j].n) *
                  m.groups[i * b + j].mean_offset);
      row_n += m.groups[i * b + j].n;
    }
    const long double row_mean = row_sum.Value() / static_cast<long double>(row_n);
    const long double d = row_mean - m.grand_mean_offset;
    sa.Add(static_cast<long double>(row_n) * d * d);
    for (std::size_t j = 0; j < b; ++j) {
      const long double e = m.groups[i * b + j].mean_offset - row_mean;
      within_rows.Add(static_cast<long double>(m.groups[i * b + j].n) * e * e);
    }
  }
  long double ss_b = within_rows.Value() - ss_ab;
  if (ss_b < 0.0L) ss_b = 0.0L;
  return {sa.Value(), ss_b};
}

}  // namespace

TwoWayAnovaResult TwoWayAnova(const std::vector<double>& response,
                              const std::vector<std::string>& factor_a,
                              const std::vector<std::string>& factor_b,
                              const TwoWayOptions& options) {
  CheckPairing(response, factor_a, factor_b, options);
  if (response.empty()) throw std::invalid_argument("no observations for the two-way ANOVA");
  TwoWayAnovaResult r;
  r.type = options.type;
  const auto ia = Index(factor_a, options.name_a, r.levels_a);
  const auto ib = Index(factor_b, options.name_b, r.levels_b);
  const std::size_t a = r.levels_a.size(), b = r.levels_b.size(), n = response.size();
  const GroupedData cells = Cells(response, ia, ib, options, r.levels_a, r.levels_b);
  if (n <= a * b) {
    std::ostringstream os;
    os << n << " observations in " << a * b << " cells leave no degrees of freedom for error; "
       << "replicate at least one cell";
    throw std::invalid_argument(os.str());
  }
  const Moments m = ComputeMoments(cells);
  const auto cells_n = static_cast<Eigen::Index>(a * b);
  VectorL means(cells_n), inverse_n(cells_n);
  AccurateSum sse, ss_cells;
  r.cell_counts.assign(a, std::vector<std::size_t>(b));
  r.cell_means.assign(a, std::vector<double>(b));
  for (std::size_t c = 0; c < a * b; ++c) {
    const GroupMoments& g = m.groups[c];
    means(static_cast<Eigen::Index>(c)) = g.mean_offset;
    inverse_n(static_cast<Eigen::Index>(c)) = 1.0L / static_cast<long double>(g.n);
    sse.Add(g.sum_sq);
    const long double d = g.mean_offset - m.grand_mean_offset;
    ss_cells.Add(static_cast<long double>(g.n) * d * d);
    r.cell_counts[c / b][c % b] = g.n;
    r.cell_means[c / b][c % b] =
        static_cast<double>(static_cast<long double>(m.shift) + g.mean_offset);
  }
  r.balanced = true;
  for (const auto& row : r.cell_counts)
    for (std::size_t count : row) r.balanced = r.balanced && count == r.cell_counts[0][0];
  const long double ss_error = sse.Value();
  if (!(ss_error > 0.0L)) {
    throw std::invalid_argument(
        "every cell is constant (error sum of squares is 0); the F ratios would be infinite");
  }
  const std::size_t df_error = n - a * b;
  const long double mse = ss_error / static_cast<long double>(df_error);
  const long double ss_ab = HypothesisSS(ContrastAB(a, b), means, inverse_n);
  long double ss_a = 0.0L, ss_b = 0.0L;
  if (options.type == SumOfSquaresType::kTypeIII) {
    ss_a = HypothesisSS(ContrastA(a, b), means, inverse_n);
    ss_b = HypothesisSS(ContrastB(a, b), means, inverse_n);
  } else {
    std::tie(ss_a, ss_b) = TypeISums(m, a, b, ss_ab);
  }
  r.a = MakeRow(options.name_a, a - 1, ss_a, mse, df_error);
  r.b = MakeRow(options.name_b, b - 1, ss_b, mse, df_error);
  r.ab = MakeRow(options.name_a + ":" + options.name_b, (a - 1) * (b - 1), ss_ab, mse, df_error);
  r.error.source = "error";
  r.error.df = df_error;
  r.error.ss = static_cast<double>(ss_error);
  r.error.ms = static_cast<double>(mse);
  r.error.f = std::numeric_limits<double>::quiet_NaN();
  r.error.p = std::numeric_limits<double>::quiet_NaN();
  r.df_total = n - 1;
  r.ss_total = static_cast<double>(ss_cells.Value() + ss_error);
  return r;
}

}  // namespace hoof::stats
