#include "studyfile/table_archive.h"

#include <cmath>
#include <limits>

namespace hoof::studyfile {

TableReader::TableReader(const Table& table, std::string where)
    : table_(table), where_(std::move(where)) {
  rows_ = table_.columns.empty() ? 0 : table_.columns.front().size();
}

std::runtime_error TableReader::Error(const std::string& column, const std::string& what) const {
  return std::runtime_error(where_ + ": column \"" + column + "\" " + what);
}

const Column* TableReader::Find(const std::string& name, Presence presence) const {
  for (const Column& c : table_.columns)
    if (c.name == name) return &c;
  if (presence == Presence::kAddedLater) return nullptr;
  throw Error(name, "is missing");
}

double TableReader::NumberAt(const Column& c) const {
  if (const auto* d = std::get_if<std::vector<double>>(&c.values)) return (*d)[row_];
  if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values))
    return static_cast<double>((*i)[row_]);
  throw Error(c.name, "is not numeric");
}

void TableReader::Number(const std::string& name, double& v, const std::string& /*units*/,
                         const std::string& /*description*/, Presence presence) const {
  if (const Column* c = Find(name, presence)) v = NumberAt(*c);
}

std::int64_t TableReader::IntegerAt(const Column& c) const {
  if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values)) return (*i)[row_];
  const double x = NumberAt(c);
  if (!(std::abs(x) <= 9.0e15) || x != std::trunc(x))
    throw Error(c.name,
                "row " + std::to_string(row_) + ": " + std::to_string(x) + " is not an integer");
  return static_cast<std::int64_t>(x);
}

void TableReader::Flag(const std::string& name, bool& v, const std::string& description,
                       Presence presence) const {
  std::int64_t x = v ? 1 : 0;
  Integer(name, x, "", description, presence);
  v = x != 0;
}

void TableReader::Text(const std::string& name, std::string& v, const std::string& /*description*/,
                       Presence presence) const {
  const Column* c = Find(name, presence);
  if (!c) return;
  const auto* s = std::get_if<std::vector<std::string>>(&c->values);
  if (!s) throw Error(name, "is not text");
  v = (*s)[row_];
}

}  // namespace hoof::studyfile
