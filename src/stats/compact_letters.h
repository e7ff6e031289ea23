#pragma once
/// @file
/// The compact letter display of all pairwise comparisons, as papers print the groups of
/// Fisher's LSD: each group gets one or more letters, and two groups share a letter exactly
/// when they do not differ significantly ("5.53 a, 5.03 ab, 4.66 b").
///
/// Written by hand (no Debian C++ library offers it) after Piepho's insert-and-absorb
/// algorithm (H.-P. Piepho, "An algorithm for a letter-based representation of all-pairwise
/// comparisons", J. Comput. Graph. Stat. 13(2), 2004, 456-466):
///  1. one column (letter) holds every group;
///  2. insert: for each significant pair (i, j), in the order i < j, every column holding both
///     is replaced by two copies, one without i and one without j;
///     absorb: then every column whose groups all lie in another column is dropped (the later
///     of two equal columns);
///  3. sweep: a group's letter is dropped where the group keeps another letter and every other
///     group in that column shares another letter with it; columns left empty are dropped.
/// The result is a valid display (shares a letter exactly when not significant) without a
/// column inside another; it need not have the fewest letters, which is NP-hard in general
/// (Gramm et al., Comput. Stat. Data Anal. 52, 2007, 725-736), though it does on the small
/// designs of a study.
///
/// Letters are then named in the order of the means, highest first: "a" is the letter of the
/// group with the highest mean, and of two letters the one whose highest-mean group has the
/// higher mean comes first (ties by the next groups, then by group order). Letters run a..z,
/// then A..Z; beyond 52 a letter is written "{53}", "{54}", ...

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace hoof::stats {

/// The letters of each group.
struct LetterDisplay {
  /// letters[g]: the letters of group g (input order), in alphabetical order ("ab").
  std::vector<std::string> letters;
  /// columns[l]: the groups (input order indices) carrying letter l, ascending.
  std::vector<std::vector<std::size_t>> columns;
};

/// The name of letter `index` (0 -> "a", 25 -> "z", 26 -> "A", 52 -> "{53}").
std::string LetterName(std::size_t index);

/// The display of `different` (k x k, symmetric, false on the diagonal: whether groups i and j
/// differ significantly) for groups of means `means` (k finite values, which name the letters).
/// Throws std::invalid_argument when k = 0, the sizes disagree, the matrix is not symmetric or
/// its diagonal is set, or a mean is not finite.
LetterDisplay CompactLetters(const std::vector<double>& means,
                             const std::vector<std::vector<bool>>& different);

/// The same for groups named by `labels` (distinct, one per mean), with the significantly
/// different pairs named by label (e.g. Fisher's LSD pairs whose p < alpha); a pair not listed
/// does not differ, so no pair gives every group "a". Throws std::invalid_argument as above, for
/// labels that repeat or are fewer than the means, and for a pair naming a label not in
/// `labels` or a group with itself.
LetterDisplay CompactLetters(const std::vector<std::string>& labels,
                             const std::vector<double>& means,
                             const std::vector<std::pair<std::string, std::string>>& different);

}  // namespace hoof::stats
