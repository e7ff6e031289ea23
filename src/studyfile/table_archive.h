#pragma once
/// @file
/// Rows of a struct as a Table of the study file and back. The fields of a row are declared
/// once, in a Serialize(archive, row) function that names each column with its units and
/// description; TableWriter::Of turns rows into a Table, TableReader::Read turns a Table back
/// into rows. The same list drives both directions (the pattern of studyfile/archive.h, for
/// tables), so a column cannot be written under one name and read under another.
///
/// Serialize is a template on the archive and on the row's constness: a writer visits const
/// rows, a reader mutable ones.
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "studyfile/study_file.h"

namespace hoof::studyfile {

/// How an enum field is spelled in its text column, both ways.
template <class Enum>
struct EnumText {
  const char* (*to_text)(Enum);
  Enum (*from_text)(const std::string&);  ///< throws on text it does not know
};

/// Whether files written before a column existed may lack it. A reader leaves such a field at
/// its default when the column is missing.
enum class Presence { kRequired, kAddedLater };

/// Builds a Table from rows.
class TableWriter {
 public:
  static constexpr bool kWriting = true;

  /// The table `name` of `rows`, each visited by `serialize(writer, row)`. The columns are
  /// declared by a visit of `declared` (a default row unless given: a row whose columns depend
  /// on its contents, such as one per marker, passes one that has them all), so a table of no
  /// rows still has them.
  template <class Row, class Serializer>
  static Table Of(std::string name, std::string description, const std::vector<Row>& rows,
                  Serializer&& serialize, const Row& declared = Row{}) {
    TableWriter w;
    serialize(w, declared);
    w.declaring_ = false;
    for (const Row& row : rows) {
      w.next_ = 0;
      serialize(w, row);
      if (w.next_ != w.columns_.size())
        throw std::logic_error("table " + name + ": a row visits fewer columns than declared");
    }
    return Table{std::move(name), std::move(description), std::move(w.columns_)};
  }
  /// A table of the one row `row`.
  template <class Row, class Serializer>
  static Table OfOne(std::string name, std::string description, const Row& row,
                     Serializer&& serialize) {
    TableWriter w;
    serialize(w, row);
    w.declaring_ = false;
    serialize(w, row);
    return Table{std::move(name), std::move(description), std::move(w.columns_)};
  }

  void Number(const std::string& name, double v, const std::string& units,
              const std::string& description, Presence = Presence::kRequired) {
    Put(name, v, [&] { return Column::Numbers(name, units, description, {}); });
  }
  void Integer(const std::string& name, std::int64_t v, const std::string& units,
               const std::string& description, Presence = Presence::kRequired) {
    Put(name, v, [&] { return Column::Integers(name, units, description, {}); });
  }
  /// A boolean, as the integers 0 and 1 (units "").
  void Flag(const std::string& name, bool v, const std::string& description,
            Presence = Presence::kRequired) {
    Put(name, std::int64_t{v ? 1 : 0}, [&] { return Column::Integers(name, "", description, {}); });
  }
  void Text(const std::string& name, const std::string& v, const std::string& description,
            Presence = Presence::kRequired) {
    Put(name, v, [&] { return Column::Texts(name, description, {}); });
  }
  template <class Enum>
  void Choice(const std::string& name, Enum v, const EnumText<Enum>& text,
              const std::string& description, Presence = Presence::kRequired) {
    Put(name, std::string(text.to_text(v)), [&] { return Column::Texts(name, description, {}); });
  }

 private:
  TableWriter() = default;

  template <class T, class Make>
  void Put(const std::string& name, T value, Make make) {
    if (declaring_) {
      columns_.push_back(make());
      return;
    }
    // A row that visits other columns than the declaration did is a bug of its Serialize.
    if (next_ >= columns_.size() || columns_[next_].name != name)
      throw std::logic_error("table row visits column \"" + name + "\" out of its declared order");
    std::get<std::vector<T>>(columns_[next_++].values).push_back(std::move(value));
  }

  std::vector<Column> columns_;
  std::size_t next_ = 0;
  bool declaring_ = true;
};

/// Reads rows back from a Table. Errors name `where` (the file and the table), the column and
/// the row.
class TableReader {
 public:
  static constexpr bool kWriting = false;

  /// The rows of `table`, each filled by `serialize(reader, row)` from a default Row.
  template <class Row, class Serializer>
  static std::vector<Row> Read(const Table& table, std::string where, Serializer&& serialize) {
    TableReader r(table, std::move(where));
    std::vector<Row> rows(r.rows_);
    for (r.row_ = 0; r.row_ < r.rows_; ++r.row_) serialize(r, rows[r.row_]);
    return rows;
  }
  /// Fills `row` from a table that must hold exactly one row.
  template <class Row, class Serializer>
  static void ReadOne(const Table& table, std::string where, Row& row, Serializer&& serialize) {
    TableReader r(table, std::move(where));
    if (r.rows_ != 1)
      throw std::runtime_error(r.where_ + " has " + std::to_string(r.rows_) + " rows, not 1");
    serialize(r, row);
  }

  void Number(const std::string& name, double& v, const std::string& /*units*/,
              const std::string& /*description*/, Presence presence = Presence::kRequired) const;
  /// Any integer type; a value out of its range is an error naming the row.
  template <std::integral I>
  void Integer(const std::string& name, I& v, const std::string& /*units*/,
               const std::string& /*description*/, Presence presence = Presence::kRequired) const {
    const Column* c = Find(name, presence);
    if (!c) return;
    const std::int64_t x = IntegerAt(*c);
    if (x < std::numeric_limits<I>::min() || x > std::numeric_limits<I>::max())
      throw Error(name,
                  "row " + std::to_string(row_) + ": " + std::to_string(x) + " is out of range");
    v = static_cast<I>(x);
  }
  void Flag(const std::string& name, bool& v, const std::string& /*description*/,
            Presence presence = Presence::kRequired) const;
  void Text(const std::string& name, std::string& v, const std::string& /*description*/,
            Presence presence = Presence::kRequired) const;
  template <class Enum>
  void Choice(const std::string& name, Enum& v, const EnumText<Enum>& text,
              const std::string& description, Presence presence = Presence::kRequired) const {
    std::string s;
    Text(name, s, description, presence);
    if (presence == Presence::kAddedLater && !Find(name, presence)) return;
    try {
      v = text.from_text(s);
    } catch (const std::exception& e) {
      throw Error(name, "row " + std::to_string(row_) + ": " + e.what());
    }
  }

  /// The error for column `column`: "<where>: column "<column>" <what>".
  std::runtime_error Error(const std::string& column, const std::string& what) const;

 private:
  TableReader(const Table& table, std::string where);
  /// The column `name`; nullptr when it is missing and may be, else an error.
  const Column* Find(const std::string& name, Presence presence) const;
  /// The number in row_ of a numeric column (doubles or integers).
  double NumberAt(const Column& c) const;
  /// The integer in row_ of a numeric column (a double must hold an integer).
  std::int64_t IntegerAt(const Column& c) const;

  const Table& table_;
  std::string where_;
  std::size_t rows_ = 0, row_ = 0;
};

}  // namespace hoof::studyfile
