// The scorecard's tables (bench/scorecard.h; docs/discovery.md, "Scorecard").
#include "scorecard.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "discovery/discovery.h"
#include "stats/distributions.h"

namespace scorecard {
namespace {

std::pair<double, double> Wilson(int k, int n) {
  if (n == 0) return {NAN, NAN};
  return hoof::stats::WilsonInterval(k, n);
}

std::string Rate(int k, int n) {
  if (n == 0) return "-";
  const auto [lo, hi] = Wilson(k, n);
  char buf[96];
  std::snprintf(buf, sizeof buf, "%d/%d = %.2f [%.2f, %.2f]", k, n, static_cast<double>(k) / n, lo,
                hi);
  return buf;
}

void PrintTable(const std::vector<std::string>& header,
                const std::vector<std::vector<std::string>>& rows) {
  const auto line = [](const std::vector<std::string>& cells) {
    std::cout << "|";
    for (const auto& c : cells) std::cout << " " << c << " |";
    std::cout << "\n";
  };
  line(header);
  std::cout << "|";
  for (std::size_t i = 0; i < header.size(); ++i) std::cout << (i == 0 ? "---|" : "--:|");
  std::cout << "\n";
  for (const auto& r : rows) line(r);
  std::cout << "\n";
}

std::string SizeLabel(const Row& r) {
  return r.point.effect->key == "null"
             ? "null"
             : r.point.effect->key + " " + Num(r.point.size) + " " + r.point.effect->unit;
}

bool WrongName(const Row& r) {
  for (const auto& n : r.named)
    if (!NamesHidden(*r.point.effect, n)) return true;
  return false;
}

bool Detected(const Row& r) {
  for (const auto& n : r.named)
    if (NamesHidden(*r.point.effect, n)) return true;
  return false;
}

void PrintConfusion(const std::vector<Row>& rows, const std::string& design, double scatter) {
  std::vector<std::string> columns = LibraryKeys();
  for (const Row& r : rows)
    for (const auto& n : r.named)
      if (std::find(columns.begin(), columns.end(), n) == columns.end()) columns.push_back(n);
  std::vector<std::string> labels;
  std::map<std::string, std::map<std::string, int>> counts;
  for (const Row& r : rows) {
    if (r.point.design != design || r.point.scatter != scatter) continue;
    const std::string label = SizeLabel(r);
    if (std::find(labels.begin(), labels.end(), label) == labels.end()) labels.push_back(label);
    const std::string column = !r.discovered        ? "error"
                               : r.named.empty()    ? "nothing"
                               : r.named.size() > 1 ? "several"
                                                    : r.named.front();
    ++counts[label][column];
  }
  if (labels.empty()) return;
  columns.insert(columns.end(), {"nothing", "several", "error"});
  std::vector<std::string> header = {"hidden \\ named"};
  header.insert(header.end(), columns.begin(), columns.end());
  std::vector<std::vector<std::string>> table;
  for (const auto& label : labels) {
    std::vector<std::string> cells = {label};
    for (const auto& c : columns) {
      const int n = counts[label].count(c) ? counts[label][c] : 0;
      cells.push_back(n ? std::to_string(n) : ".");
    }
    table.push_back(cells);
  }
  std::cout << "### Confusion: " << design << ", scatter " << Num(scatter) << "\n\n";
  PrintTable(header, table);
}

/// Power: the rate at which the hidden effect is named, per effect and size, per design and
/// scatter.
void PrintPower(const std::vector<Row>& rows,
                const std::vector<std::pair<std::string, double>>& combos) {
  std::vector<std::string> header = {"hidden effect"};
  for (const auto& [d, s] : combos) header.push_back(d + ", scatter " + Num(s));
  std::vector<std::string> labels;
  for (const Row& r : rows)
    if (r.point.effect->key != "null" &&
        std::find(labels.begin(), labels.end(), SizeLabel(r)) == labels.end())
      labels.push_back(SizeLabel(r));
  std::vector<std::vector<std::string>> table;
  for (const auto& label : labels) {
    std::vector<std::string> cells = {label};
    for (const auto& [d, s] : combos) {
      int k = 0, n = 0;
      for (const Row& r : rows)
        if (r.discovered && SizeLabel(r) == label && r.point.design == d && r.point.scatter == s) {
          ++n;
          k += Detected(r) ? 1 : 0;
        }
      cells.push_back(Rate(k, n));
    }
    table.push_back(cells);
  }
  if (!table.empty()) {
    std::cout << "### Power: hidden effect named (rate, Wilson 95 %)\n\n";
    PrintTable(header, table);
  }
}

/// Power against the size in units of the detection limit discovery printed for each study:
/// where the limits are right, about 80 % at 1 and at least 90 % from 2.
void PrintPowerAgainstLimit(const std::vector<Row>& rows) {
  const std::vector<double> edges = {0.0, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 1e300};
  std::vector<std::string> effects;
  for (const Row& r : rows)
    if (r.point.effect->key != "null" &&
        std::find(effects.begin(), effects.end(), r.point.effect->key) == effects.end())
      effects.push_back(r.point.effect->key);
  std::vector<std::string> head = {"size / printed limit"};
  for (const auto& e : effects) head.push_back(e);
  head.push_back("all");
  std::vector<std::vector<std::string>> bins;
  for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
    std::vector<std::string> cells = {
        b + 2 < edges.size() ? Num(edges[b]) + " - " + Num(edges[b + 1]) : ">= " + Num(edges[b])};
    int all_k = 0, all_n = 0;
    for (std::size_t j = 0; j <= effects.size(); ++j) {
      int k = 0, n = 0;
      for (const Row& r : rows) {
        if (!r.discovered || r.point.effect->key == "null" || !(r.limit > 0)) continue;
        if (j < effects.size() && r.point.effect->key != effects[j]) continue;
        const double x = r.point.size / r.limit;
        if (x < edges[b] || x >= edges[b + 1]) continue;
        ++n;
        k += Detected(r) ? 1 : 0;
      }
      if (j == effects.size()) all_k = k, all_n = n;
      cells.push_back(j == effects.size()
                          ? Rate(all_k, all_n)
                          : (n ? std::to_string(k) + "/" + std::to_string(n) : "-"));
    }
    bins.push_back(cells);
  }
  std::cout << "### Power against the printed detection limit (hidden effect named; size over "
               "the limit "
               "discovery printed for that study in round 1)\n\n";
  PrintTable(head, bins);
}

/// False naming on null studies and wrong names over all studies.
void PrintNames(const std::vector<Row>& rows,
                const std::vector<std::pair<std::string, double>>& combos) {
  std::vector<std::vector<std::string>> table;
  const auto add = [&](const std::string& label, const std::function<bool(const Row&)>& in) {
    int null_k = 0, null_n = 0, wrong_k = 0, wrong_n = 0;
    for (const Row& r : rows) {
      if (!r.discovered || !in(r)) continue;
      ++wrong_n;
      wrong_k += WrongName(r) ? 1 : 0;
      if (r.point.effect->key == "null") {
        ++null_n;
        null_k += r.named.empty() ? 0 : 1;
      }
    }
    table.push_back({label, Rate(null_k, null_n), Rate(wrong_k, wrong_n)});
  };
  for (const auto& combo : combos)
    add(combo.first + ", scatter " + Num(combo.second), [&combo](const Row& r) {
      return r.point.design == combo.first && r.point.scatter == combo.second;
    });
  add("all", [](const Row&) { return true; });
  std::cout << "### False and wrong names (rate, Wilson 95 %)\n\n"
               "False naming: a null study in which anything is named. Wrong effect: a study "
               "in which a key other than the hidden effect's is named.\n\n";
  PrintTable({"studies", "false naming (null studies)", "wrong effect (all studies)"}, table);
}

/// Time per study and size of a cache entry, per design.
void PrintTimes(const std::vector<Row>& rows, const std::vector<std::string>& designs) {
  std::vector<std::vector<std::string>> table;
  for (const auto& d : designs) {
    double render = 0, analyze = 0, discover = 0, bytes = 0;
    int n_made = 0, n_disc = 0, n_bytes = 0, trials = 0;
    for (const Row& r : rows) {
      if (r.point.design != d) continue;
      if (std::isfinite(r.render_s) && std::isfinite(r.analyze_s)) {
        render += r.render_s;
        analyze += r.analyze_s;
        trials = r.trials;
        ++n_made;
      }
      if (std::isfinite(r.discover_s)) {
        discover += r.discover_s;
        ++n_disc;
      }
      if (std::isfinite(r.cache_bytes)) {
        bytes += r.cache_bytes;
        ++n_bytes;
      }
    }
    const auto mean = [](double sum, int n) {
      char buf[32];
      if (n == 0) return std::string("-");
      std::snprintf(buf, sizeof buf, "%.1f", sum / n);
      return std::string(buf);
    };
    table.push_back({d, std::to_string(trials), mean(render, n_made), mean(analyze, n_made),
                     mean(discover, n_disc), mean(bytes / 1e6, n_bytes),
                     std::to_string(n_made) + " / " + std::to_string(n_disc)});
  }
  std::cout << "### Time per study (mean wall seconds; render and analysis as recorded when the "
               "study was cached)\n\n";
  PrintTable({"design", "trials", "render s", "analyze s", "discover s", "cache entry MB",
              "studies (made / discovered)"},
             table);
}

}  // namespace

void PrintReport(const std::vector<Row>& rows, const std::vector<std::string>& designs,
                 const std::vector<double>& scatters, bool only_render) {
  std::cout << "# Discovery scorecard\n\n";
  std::vector<std::pair<std::string, double>> combos;
  for (const auto& d : designs)
    for (double s : scatters) combos.push_back({d, s});
  if (!only_render) {
    for (const auto& [d, s] : combos) PrintConfusion(rows, d, s);
    PrintPower(rows, combos);
    PrintPowerAgainstLimit(rows);
    PrintNames(rows, combos);
  }
  PrintTimes(rows, designs);
  int errors = 0;
  for (const Row& r : rows) errors += r.stage.empty() ? 0 : 1;
  std::cout << "Studies: " << rows.size() << ", errors: " << errors << "\n";
  for (const Row& r : rows)
    if (!r.stage.empty())
      std::cout << "  ERROR (" << r.stage << ") " << r.point.Label() << ": " << r.error << "\n";
}

nlohmann::json RowJson(const Row& r) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"design", r.point.design},
          {"scatter", r.point.scatter},
          {"effect", r.point.effect->key},
          {"size", r.point.size},
          {"size_unit", r.point.effect->unit},
          {"seed", r.point.seed_index},
          {"study_seed", r.study_seed},
          {"named", r.named},
          {"discovered", r.discovered},
          {"detected", Detected(r)},
          {"detection_limit", num(r.limit)},
          {"size_over_limit", num(r.point.size / r.limit)},
          {"detection_limits",
           [&] {
             nlohmann::json j = nlohmann::json::object();
             for (const auto& [k, v] : r.limits) j[k] = num(v);
             return j;
           }()},
          {"wrong_name", WrongName(r)},
          {"trials", r.trials},
          {"failed_trials", r.failed_trials},
          {"from_cache", r.from_cache},
          {"cache_file", r.cache_file.string()},
          {"cache_bytes", num(r.cache_bytes)},
          {"seconds",
           {{"render", num(r.render_s)},
            {"analyze", num(r.analyze_s)},
            {"discover", num(r.discover_s)}}},
          {"error_stage", r.stage},
          {"error", r.error}};
}

}  // namespace scorecard
