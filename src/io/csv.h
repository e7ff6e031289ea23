#pragma once
/// @file
/// A small CSV reader and writer for the tables hoofimpact reads (normal-impact velocities,
/// any table for `stats --csv`) and writes (trajectories, per-trial results).
/// RFC 4180 quoting is supported; the first row is the header.

#include <filesystem>
#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace hoof::io {

/// A parsed CSV table. Errors name the file, the 1-based line and the column.
class CsvTable {
 public:
  /// Reads `path`. Throws std::runtime_error naming the file when it cannot be read, is empty,
  /// or a row has a different number of fields from the header.
  static CsvTable Read(const std::filesystem::path& path);
  /// Parses CSV text; `source` names it in error messages.
  static CsvTable Parse(std::istream& in, const std::string& source);

  const std::vector<std::string>& header() const { return header_; }
  std::size_t rows() const { return rows_.size(); }
  const std::string& source() const { return source_; }

  /// Index of column `name`, or nullopt.
  std::optional<std::size_t> FindColumn(const std::string& name) const;
  /// Index of column `name`; throws std::runtime_error naming the file, the column and the
  /// columns that exist.
  std::size_t Column(const std::string& name) const;

  /// Field text at (row, column).
  const std::string& Text(std::size_t row, std::size_t column) const;
  /// Field as a finite number. Throws std::runtime_error naming file, line, column and value
  /// when it is empty, not a number, NaN or infinite.
  double Number(std::size_t row, std::size_t column) const;
  /// The whole column as numbers (see Number).
  std::vector<double> Numbers(const std::string& column) const;
  /// The whole column as text.
  std::vector<std::string> Texts(const std::string& column) const;
  /// 1-based line number of a data row in the source (header is line 1).
  std::size_t LineOf(std::size_t row) const { return lines_[row]; }

 private:
  std::string source_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<std::size_t> lines_;
};

/// Quotes a field for CSV output when it needs it.
std::string CsvEscape(const std::string& field);

/// Formats a double with 17 significant digits (round-trip exact), "nan" for NaN.
std::string CsvNumber(double value);

}  // namespace hoof::io
