#include "io/csv.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hoof::io {
namespace {

/// Splits one record; handles quoted fields with embedded commas, quotes and newlines
/// (reading further lines from `in` when a quote is open). Returns false at end of input.
bool ReadRecord(std::istream& in, std::vector<std::string>& fields, std::size_t& line) {
  fields.clear();
  std::string raw;
  if (!std::getline(in, raw)) return false;
  ++line;
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0;; ++i) {
    if (i == raw.size()) {
      if (quoted) {
        std::string more;
        if (!std::getline(in, more)) break;
        ++line;
        field += '\n';
        raw = more;
        i = static_cast<std::size_t>(-1);
        continue;
      }
      break;
    }
    const char ch = raw[i];
    if (quoted) {
      if (ch == '"') {
        if (i + 1 < raw.size() && raw[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        field += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      fields.push_back(field);
      field.clear();
    } else if (ch != '\r') {
      field += ch;
    }
  }
  fields.push_back(field);
  return true;
}

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

}  // namespace

CsvTable CsvTable::Read(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open CSV file");
  return Parse(in, path.string());
}

CsvTable CsvTable::Parse(std::istream& in, const std::string& source) {
  CsvTable table;
  table.source_ = source;
  std::size_t line = 0;
  std::vector<std::string> fields;
  // Header: first non-empty record.
  while (ReadRecord(in, fields, line)) {
    if (fields.size() == 1 && Trim(fields[0]).empty()) continue;
    for (auto& f : fields) table.header_.push_back(Trim(f));
    break;
  }
  if (table.header_.empty()) throw std::runtime_error(source + ": CSV file has no header row");
  while (true) {
    const std::size_t start = line + 1;
    if (!ReadRecord(in, fields, line)) break;
    if (fields.size() == 1 && Trim(fields[0]).empty()) continue;  // blank line
    if (fields.size() != table.header_.size()) {
      std::ostringstream os;
      os << source << ":" << start << ": expected " << table.header_.size()
         << " fields as in the header, found " << fields.size();
      throw std::runtime_error(os.str());
    }
    for (auto& f : fields) f = Trim(f);
    table.rows_.push_back(fields);
    table.lines_.push_back(start);
  }
  return table;
}

std::optional<std::size_t> CsvTable::FindColumn(const std::string& name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return i;
  return std::nullopt;
}

std::size_t CsvTable::Column(const std::string& name) const {
  if (auto i = FindColumn(name)) return *i;
  std::string have;
  for (const auto& h : header_) have += (have.empty() ? "" : ", ") + h;
  throw std::runtime_error(source_ + ": no column \"" + name + "\" (columns: " + have + ")");
}

const std::string& CsvTable::Text(std::size_t row, std::size_t column) const {
  return rows_.at(row).at(column);
}

double CsvTable::Number(std::size_t row, std::size_t column) const {
  const std::string& text = Text(row, column);
  double value = 0.0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (!text.empty() && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value)) {
    std::ostringstream os;
    os << source_ << ":" << lines_[row] << ": column \"" << header_[column] << "\" value \"" << text
       << "\" is not a finite number";
    throw std::runtime_error(os.str());
  }
  return value;
}

std::vector<double> CsvTable::Numbers(const std::string& column) const {
  const std::size_t c = Column(column);
  std::vector<double> out;
  out.reserve(rows_.size());
  for (std::size_t r = 0; r < rows_.size(); ++r) out.push_back(Number(r, c));
  return out;
}

std::vector<std::string> CsvTable::Texts(const std::string& column) const {
  const std::size_t c = Column(column);
  std::vector<std::string> out;
  out.reserve(rows_.size());
  for (const auto& row : rows_) out.push_back(row[c]);
  return out;
}

std::string CsvEscape(const std::string& field) {
  if (field.find_first_of(",\"\n\r") == std::string::npos) return field;
  std::string out = "\"";
  for (char ch : field) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + "\"";
}

std::string CsvNumber(double value) {
  if (std::isnan(value)) return "nan";
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, ec == std::errc() ? ptr : buf);
}

}  // namespace hoof::io
