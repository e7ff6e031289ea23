#include "stats/grouping.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "stats/moments.h"

namespace hoof::stats {
namespace {

void RequireFinite(double value, std::size_t index, const std::string& label) {
  if (std::isfinite(value)) return;
  std::ostringstream os;
  os << "observation " << index << " (group \"" << label << "\") is "
     << (std::isnan(value) ? "NaN" : "infinite") << "; every response value must be finite";
  throw std::invalid_argument(os.str());
}

}  // namespace

std::size_t GroupedData::observations() const {
  std::size_t n = 0;
  for (const auto& v : values) n += v.size();
  return n;
}

GroupedData GroupByLabel(const std::vector<double>& response,
                         const std::vector<std::string>& labels) {
  if (response.size() != labels.size()) {
    std::ostringstream os;
    os << "response has " << response.size() << " values but there are " << labels.size()
       << " group labels; they must pair one to one";
    throw std::invalid_argument(os.str());
  }
  if (response.empty()) throw std::invalid_argument("no observations to group");
  GroupedData data;
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < response.size(); ++i) {
    const std::string& label = labels[i];
    if (label.empty()) {
      std::ostringstream os;
      os << "observation " << i << " has an empty group label";
      throw std::invalid_argument(os.str());
    }
    RequireFinite(response[i], i, label);
    auto [it, inserted] = index.try_emplace(label, data.labels.size());
    if (inserted) {
      data.labels.push_back(label);
      data.values.emplace_back();
    }
    data.values[it->second].push_back(response[i]);
  }
  return data;
}

GroupedData MakeGroups(const std::vector<std::string>& labels,
                       const std::vector<std::vector<double>>& values) {
  if (labels.size() != values.size()) {
    std::ostringstream os;
    os << labels.size() << " group labels for " << values.size() << " groups";
    throw std::invalid_argument(os.str());
  }
  std::vector<double> response;
  std::vector<std::string> flat_labels;
  for (std::size_t g = 0; g < values.size(); ++g) {
    if (values[g].empty())
      throw std::invalid_argument("group \"" + labels[g] + "\" has no observations");
    for (double v : values[g]) {
      response.push_back(v);
      flat_labels.push_back(labels[g]);
    }
  }
  GroupedData data = GroupByLabel(response, flat_labels);
  if (data.groups() != labels.size()) {
    throw std::invalid_argument("group labels must be distinct");
  }
  return data;
}

void ValidateOneWay(const GroupedData& data) {
  if (data.groups() < 2) {
    std::ostringstream os;
    os << "one-way analysis needs at least 2 groups; found " << data.groups();
    if (data.groups() == 1) os << " (\"" << data.labels[0] << "\")";
    throw std::invalid_argument(os.str());
  }
  for (std::size_t g = 0; g < data.groups(); ++g) {
    if (data.values[g].size() < 2) {
      std::ostringstream os;
      os << "group \"" << data.labels[g] << "\" has " << data.values[g].size()
         << " observation; each group needs at least 2 (its variance enters Bartlett's and "
            "Welch's tests)";
      throw std::invalid_argument(os.str());
    }
  }
  const double first = data.values[0][0];
  for (const auto& group : data.values)
    for (double v : group)
      if (v != first) return;
  std::ostringstream os;
  os.precision(17);
  os << "all " << data.observations() << " observations equal " << first
     << "; constant data have nothing to analyse";
  throw std::invalid_argument(os.str());
}

std::vector<GroupSummary> Summarize(const GroupedData& data) {
  const Moments m = ComputeMoments(data);
  std::vector<GroupSummary> out;
  out.reserve(data.groups());
  for (std::size_t g = 0; g < data.groups(); ++g) {
    GroupSummary s;
    s.label = data.labels[g];
    s.n = m.groups[g].n;
    s.mean = static_cast<double>(static_cast<long double>(m.shift) + m.groups[g].mean_offset);
    s.variance =
        s.n > 1 ? static_cast<double>(m.groups[g].sum_sq / static_cast<long double>(s.n - 1)) : 0.0;
    s.sd = std::sqrt(s.variance);
    out.push_back(s);
  }
  return out;
}

}  // namespace hoof::stats
