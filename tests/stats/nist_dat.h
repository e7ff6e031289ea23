#pragma once
// Reads the NIST StRD one-way ANOVA files in tests/data/nist/: lines starting with '#' are
// comments (they carry the source and the certified values), every other non-blank line is
// "label value". Each value is kept three ways: its decimal text, the nearest double (what a
// program reading the file gets), and the value times 10^d as an exact integer (d = the most
// digits after the decimal point in the file), which double holds exactly.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hoof::stats::testing {

struct NistAnovaFile {
  std::vector<std::string> labels;
  std::vector<std::string> texts;  ///< The response as written.
  std::vector<double> values;      ///< Nearest double to each text.
  int decimals = 0;                ///< d: most digits after the point.
  std::vector<double> scaled;      ///< value * 10^d, exact (|value * 10^d| < 2^53).
};

/// Path of tests/data/nist/<name>.dat in the source tree.
inline std::string NistPath(const std::string& name) {
  return std::string(HOOF_SOURCE_DIR) + "/tests/data/nist/" + name + ".dat";
}

/// The decimal text times 10^decimals as an exact integer.
inline std::int64_t ScaledInteger(const std::string& text, int decimals) {
  const auto dot = text.find('.');
  std::string digits = text;
  int have = 0;
  if (dot != std::string::npos) {
    digits = text.substr(0, dot) + text.substr(dot + 1);
    have = static_cast<int>(text.size() - dot - 1);
  }
  for (int i = have; i < decimals; ++i) digits += '0';
  std::size_t used = 0;
  const long long v = std::stoll(digits, &used);
  if (used != digits.size()) throw std::runtime_error("not a decimal number: " + text);
  if (std::llabs(v) >= (1LL << 53)) throw std::runtime_error("too many digits: " + text);
  return v;
}

inline NistAnovaFile ReadNistAnova(const std::string& name) {
  std::ifstream in(NistPath(name));
  if (!in) throw std::runtime_error("cannot open " + NistPath(name));
  NistAnovaFile f;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string label, text;
    if (!(fields >> label >> text)) throw std::runtime_error("bad line in " + name + ": " + line);
    f.labels.push_back(label);
    f.texts.push_back(text);
    f.values.push_back(std::stod(text));
    const auto dot = text.find('.');
    if (dot != std::string::npos)
      f.decimals = std::max(f.decimals, static_cast<int>(text.size() - dot - 1));
  }
  for (const auto& t : f.texts)
    f.scaled.push_back(static_cast<double>(ScaledInteger(t, f.decimals)));
  return f;
}

/// Log relative error, the "digits of agreement" measure of the NIST StRD reports:
/// -log10(|x - c| / |c|), capped at 15.
inline double Lre(double x, double c) {
  if (x == c) return 15.0;
  return std::min(15.0, -std::log10(std::fabs(x - c) / std::fabs(c)));
}

}  // namespace hoof::stats::testing
