#include "study/normal_impacts.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "io/csv.h"

namespace hoof::study {

bool SameValue(const std::string& text, const std::string& value) {
  if (text == value) return true;
  auto number = [](const std::string& t, double& x) {
    if (t.empty()) return false;
    char* end = nullptr;
    x = std::strtod(t.c_str(), &end);
    return end == t.c_str() + t.size() && std::isfinite(x);
  };
  double x = 0.0, y = 0.0;
  return number(text, x) && number(value, y) && x == y;
}

std::map<std::string, std::vector<dynamics::NormalImpact>> ReadNormalImpacts(
    const std::string& csv_path, const NormalImpactColumns& columns) {
  const io::CsvTable table = io::CsvTable::Read(csv_path);
  const std::size_t before_col = table.Column(columns.before);
  const std::size_t after_col = table.Column(columns.after);
  const auto group_index = table.FindColumn(columns.group);
  std::vector<std::pair<std::size_t, std::string>> where;
  for (const auto& f : columns.where) {
    const auto eq = f.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument("\"" + f + "\" is invalid: expected COL=VALUE");
    where.emplace_back(table.Column(f.substr(0, eq)), f.substr(eq + 1));
  }
  auto keep = [&](std::size_t r) {
    for (const auto& [col, value] : where)
      if (!SameValue(table.Text(r, col), value)) return false;
    return true;
  };
  std::map<std::string, std::vector<dynamics::NormalImpact>> groups;
  std::vector<std::size_t> above_one;  // lines with e > 1
  for (std::size_t r = 0; r < table.rows(); ++r) {
    if (!keep(r)) continue;
    // Parsed only for kept rows (a failed trial's "nan" may be filtered out). Speeds: signs
    // (a downward velocity) are ignored.
    const double before = std::abs(table.Number(r, before_col));
    const double after = std::abs(table.Number(r, after_col));
    if (!(before > 0) || !(after > 0)) {
      std::ostringstream os;
      os << csv_path << ":" << table.LineOf(r) << ": speeds must be > 0 (columns \""
         << columns.before << "\", \"" << columns.after << "\")";
      throw std::runtime_error(os.str());
    }
    if (after > before) above_one.push_back(table.LineOf(r));
    const std::string g = group_index ? table.Text(r, *group_index) : "";
    groups[g].push_back({before, after});
  }
  if (groups.empty()) throw std::runtime_error(csv_path + ": no data rows (after --where)");
  if (!above_one.empty()) {
    std::ostringstream os;
    os << csv_path << ": e = " << columns.after << " / " << columns.before << " > 1 in "
       << above_one.size() << " row(s), on line(s) ";
    for (std::size_t i = 0; i < above_one.size() && i < 10; ++i)
      os << (i ? ", " : "") << above_one[i];
    if (above_one.size() > 10) os << ", ...";
    os << ": the contact model dissipates energy and cannot fit them (swapped columns?)";
    throw std::runtime_error(os.str());
  }
  return groups;
}

std::string ValleyCsv(const std::vector<std::pair<std::string, dynamics::ContactFitSummary>>& fits,
                      double mass_kg) {
  std::ostringstream grid;
  grid << "group,k_N_m,b_N_s_m,zeta,mpe_percent,on_valley\n";
  for (const auto& [name, s] : fits) {
    for (std::size_t i = 0; i < s.map_k_N_m.size(); ++i)
      for (std::size_t j = 0; j < s.map_b_N_s_m.size(); ++j)
        grid << io::CsvEscape(name) << "," << io::CsvNumber(s.map_k_N_m[i]) << ","
             << io::CsvNumber(s.map_b_N_s_m[j]) << ","
             << io::CsvNumber(dynamics::DampingRatio(s.map_k_N_m[i], s.map_b_N_s_m[j], mass_kg))
             << ","
             << io::CsvNumber(
                    s.map_mpe_percent(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)))
             << ",0\n";
    for (const auto& p : s.valley)
      grid << io::CsvEscape(name) << "," << io::CsvNumber(p.k_N_m) << ","
           << io::CsvNumber(p.b_N_s_m) << "," << io::CsvNumber(p.zeta) << ","
           << io::CsvNumber(p.mpe_percent) << ",1\n";
  }
  return grid.str();
}

}  // namespace hoof::study
