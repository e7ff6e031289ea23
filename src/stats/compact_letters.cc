// Piepho's insert-and-absorb with sweeping, written by hand (see compact_letters.h).
#include "stats/compact_letters.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace hoof::stats {
namespace {

using Column = std::vector<char>;  // Column[g] != 0: group g carries the letter

/// Whether every group of `a` is in `b`.
bool Within(const Column& a, const Column& b) {
  for (std::size_t g = 0; g < a.size(); ++g)
    if (a[g] && !b[g]) return false;
  return true;
}

/// Drops every column that lies within another (of two equal columns, the later one).
void Absorb(std::vector<Column>& columns) {
  std::vector<char> drop(columns.size(), 0);
  for (std::size_t c = 0; c < columns.size(); ++c)
    for (std::size_t d = 0; d < columns.size() && !drop[c]; ++d) {
      if (d == c || drop[d] || !Within(columns[c], columns[d])) continue;
      // c within d: c goes, unless they are equal and c comes first (then d goes, later).
      if (columns[c] != columns[d] || c > d) drop[c] = 1;
    }
  std::vector<Column> kept;
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (!drop[c]) kept.push_back(std::move(columns[c]));
  columns = std::move(kept);
}

/// Whether groups i and k share a column other than `except`.
bool SharedElsewhere(const std::vector<Column>& columns, std::size_t except, std::size_t i,
                     std::size_t k) {
  for (std::size_t d = 0; d < columns.size(); ++d)
    if (d != except && columns[d][i] && columns[d][k]) return true;
  return false;
}

/// Piepho's sweep: drops a group's letter where another letter already links the group to
/// every group of that column; then the empty columns.
void Sweep(std::vector<Column>& columns) {
  const std::size_t k = columns.empty() ? 0 : columns.front().size();
  for (std::size_t c = 0; c < columns.size(); ++c)
    for (std::size_t i = 0; i < k; ++i) {
      if (!columns[c][i]) continue;
      bool other_letter = false;
      for (std::size_t d = 0; d < columns.size(); ++d) other_letter |= d != c && columns[d][i];
      if (!other_letter) continue;
      bool redundant = true;
      for (std::size_t m = 0; m < k && redundant; ++m)
        if (m != i && columns[c][m]) redundant = SharedElsewhere(columns, c, i, m);
      if (redundant) columns[c][i] = 0;
    }
  std::erase_if(columns,
                [](const Column& c) { return std::find(c.begin(), c.end(), 1) == c.end(); });
}

void Check(const std::vector<double>& means, const std::vector<std::vector<bool>>& different) {
  const std::size_t k = means.size();
  std::ostringstream why;
  if (k == 0) why << "needs at least one group";
  if (different.size() != k)
    why << "the significance matrix has " << different.size() << " rows for " << k << " groups";
  for (std::size_t i = 0; i < k && why.str().empty(); ++i) {
    if (!std::isfinite(means[i])) why << "the mean of group " << i << " is not finite";
    if (different[i].size() != k)
      why << "row " << i << " of the significance matrix has " << different[i].size()
          << " entries for " << k << " groups";
  }
  for (std::size_t i = 0; i < k && why.str().empty(); ++i)
    for (std::size_t j = 0; j < k && why.str().empty(); ++j) {
      if (i == j && different[i][i]) why << "group " << i << " is marked different from itself";
      if (different[i][j] != different[j][i])
        why << "the significance matrix is not symmetric at (" << i << ", " << j << ")";
    }
  if (!why.str().empty()) throw std::invalid_argument("compact letter display: " + why.str());
}

}  // namespace

std::string LetterName(std::size_t index) {
  if (index < 26) return std::string(1, static_cast<char>('a' + index));
  if (index < 52) return std::string(1, static_cast<char>('A' + (index - 26)));
  std::string name(1, '{');  // built by appending: GCC 12 misreads "{" + std::string (-Wrestrict)
  name += std::to_string(index + 1);
  name += '}';
  return name;
}

LetterDisplay CompactLetters(const std::vector<double>& means,
                             const std::vector<std::vector<bool>>& different) {
  Check(means, different);
  const std::size_t k = means.size();
  std::vector<Column> columns{Column(k, 1)};
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j) {
      if (!different[i][j]) continue;
      std::vector<Column> next;
      for (Column& c : columns) {
        if (!(c[i] && c[j])) {
          next.push_back(std::move(c));
          continue;
        }
        Column without_i = c, without_j = std::move(c);
        without_i[i] = 0;
        without_j[j] = 0;
        next.push_back(std::move(without_i));
        next.push_back(std::move(without_j));
      }
      columns = std::move(next);
      Absorb(columns);
    }
  Sweep(columns);

  // Rank of each group by mean, highest first (ties: input order); a column's key is the
  // ranks of its groups, ascending, and columns are lettered in the order of their keys.
  std::vector<std::size_t> order(k);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return means[a] > means[b]; });
  std::vector<std::size_t> rank(k);
  for (std::size_t r = 0; r < k; ++r) rank[order[r]] = r;
  std::vector<std::vector<std::size_t>> keys;
  for (const Column& c : columns) {
    std::vector<std::size_t> key;
    for (std::size_t g = 0; g < k; ++g)
      if (c[g]) key.push_back(rank[g]);
    std::sort(key.begin(), key.end());
    keys.push_back(std::move(key));
  }
  std::vector<std::size_t> lettered(columns.size());
  std::iota(lettered.begin(), lettered.end(), 0);
  std::sort(lettered.begin(), lettered.end(),
            [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });

  LetterDisplay out;
  out.letters.assign(k, "");
  for (std::size_t l = 0; l < lettered.size(); ++l) {
    const Column& c = columns[lettered[l]];
    std::vector<std::size_t> groups;
    for (std::size_t g = 0; g < k; ++g)
      if (c[g]) {
        groups.push_back(g);
        out.letters[g] += LetterName(l);
      }
    out.columns.push_back(std::move(groups));
  }
  return out;
}

LetterDisplay CompactLetters(const std::vector<std::string>& labels,
                             const std::vector<double>& means,
                             const std::vector<std::pair<std::string, std::string>>& different) {
  if (labels.size() != means.size())
    throw std::invalid_argument("compact letter display: " + std::to_string(labels.size()) +
                                " labels for " + std::to_string(means.size()) + " means");
  const auto index = [&](const std::string& label) {
    const auto it = std::find(labels.begin(), labels.end(), label);
    if (it == labels.end())
      throw std::invalid_argument("compact letter display: a pair names group \"" + label +
                                  "\", which is not among the groups");
    return static_cast<std::size_t>(it - labels.begin());
  };
  for (std::size_t g = 0; g < labels.size(); ++g)
    if (index(labels[g]) != g)
      throw std::invalid_argument("compact letter display: group \"" + labels[g] +
                                  "\" is named twice");
  std::vector<std::vector<bool>> matrix(labels.size(), std::vector<bool>(labels.size(), false));
  for (const auto& [a, b] : different) {
    const std::size_t i = index(a), j = index(b);
    if (i == j)
      throw std::invalid_argument("compact letter display: group \"" + a +
                                  "\" is marked different from itself");
    matrix[i][j] = matrix[j][i] = true;
  }
  return CompactLetters(means, matrix);
}

}  // namespace hoof::stats
