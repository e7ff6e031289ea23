// Tables of the study file: Column, Table, WriteTables and ReadTable (studyfile/study_file.h).
#include "studyfile/study_file.h"

#include <H5Cpp.h>

#include <algorithm>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "io/atomic_file.h"
#include "io/csv.h"
#include "studyfile/file_util.h"
#include "studyfile/hdf5_util.h"

namespace hoof::studyfile {
namespace {

using internal::AtomicHdf5;
using internal::RethrowHdf5;
using internal::WriteTable;

// ------------------------------------------------------------------------------------------
// Tables
// ------------------------------------------------------------------------------------------

Column ReadColumn(const H5::Group& g, const std::string& name, const std::string& where) {
  if (!g.nameExists(name)) throw std::runtime_error(where + " has no column \"" + name + "\"");
  const H5::DataSet d = g.openDataSet(name);
  const std::string here = where + "/" + name;
  Column c;
  c.name = name;
  c.units = d.attrExists("units") ? h5::GetAttrText(d, "units", here) : "";
  c.description = d.attrExists("description") ? h5::GetAttrText(d, "description", here) : "";
  if (h5::Shape(d).size() != 1) throw std::runtime_error(here + " is not one-dimensional");
  switch (d.getTypeClass()) {
    case H5T_STRING:
      c.values = h5::ReadTexts(d, here);
      break;
    case H5T_INTEGER:
      c.values = h5::ReadIntegers(d, here);
      break;
    default:
      c.values = h5::ReadDoubles(d, here);
      break;
  }
  return c;
}

}  // namespace

namespace internal {

void WriteTable(const H5::Group& parent, const Table& table) {
  const H5::Group g = h5::MakeGroup(parent, table.name, table.description);
  std::vector<std::string> names;
  for (const Column& c : table.columns) {
    names.push_back(c.name);
    const hsize_t n = c.size();
    if (const auto* d = std::get_if<std::vector<double>>(&c.values))
      h5::Doubles(g, c.name, *d, {n}, c.units, c.description);
    else if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values))
      h5::Integers(g, c.name, *i, {n}, c.units, c.description);
    else
      h5::Texts(g, c.name, std::get<std::vector<std::string>>(c.values), {n}, c.description);
  }
  h5::SetAttr(g, "columns", names);
  h5::SetAttr(g, "rows",
              static_cast<std::int64_t>(table.columns.empty() ? 0 : table.columns[0].size()));
}

}  // namespace internal

// ------------------------------------------------------------------------------------------
// Column and Table
// ------------------------------------------------------------------------------------------

std::size_t Column::size() const {
  return std::visit([](const auto& v) { return v.size(); }, values);
}

std::string Column::CsvCell(std::size_t row) const {
  if (const auto* d = std::get_if<std::vector<double>>(&values)) return io::CsvNumber((*d)[row]);
  if (const auto* n = std::get_if<std::vector<std::int64_t>>(&values))
    return std::to_string((*n)[row]);
  return io::CsvEscape(std::get<std::vector<std::string>>(values)[row]);
}

Column Column::Numbers(std::string name, std::string units, std::string description,
                       std::vector<double> values) {
  return Column{std::move(name), std::move(units), std::move(description), std::move(values)};
}

Column Column::Integers(std::string name, std::string units, std::string description,
                        std::vector<std::int64_t> values) {
  return Column{std::move(name), std::move(units), std::move(description), std::move(values)};
}

Column Column::Texts(std::string name, std::string description, std::vector<std::string> values) {
  return Column{std::move(name), "", std::move(description), std::move(values)};
}

void Table::Validate() const {
  if (name.empty() || name.front() == '/')
    throw std::invalid_argument("table name \"" + name + "\" must be non-empty and relative");
  std::set<std::string> seen;
  for (const Column& c : columns) {
    if (c.name.empty() || c.name.find('/') != std::string::npos)
      throw std::invalid_argument("table \"" + name + "\": column name \"" + c.name +
                                  "\" must be non-empty without '/'");
    if (!seen.insert(c.name).second)
      throw std::invalid_argument("table \"" + name + "\": column \"" + c.name + "\" repeats");
    if (c.size() != columns.front().size())
      throw std::invalid_argument("table \"" + name + "\": column \"" + c.name + "\" has " +
                                  std::to_string(c.size()) + " rows, column \"" +
                                  columns.front().name + "\" has " +
                                  std::to_string(columns.front().size()));
  }
}

const Column& Table::Get(const std::string& column) const {
  for (const Column& c : columns)
    if (c.name == column) return c;
  throw std::out_of_range("table \"" + name + "\" has no column \"" + column + "\"");
}

void WriteTables(const std::filesystem::path& path, const std::string& group,
                 const std::string& description, const std::vector<Table>& tables,
                 const std::function<void(std::size_t)>& after_table,
                 const std::vector<std::pair<std::string, std::string>>& soft_links) {
  if (group.size() < 2 || group.front() != '/')
    throw std::invalid_argument("group \"" + group + "\" must be an absolute path below /");
  for (const Table& t : tables) t.Validate();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such study file");
  AtomicHdf5(
      path,
      [&](const std::filesystem::path& tmp) {
        std::error_code ec;
        std::filesystem::copy_file(path, tmp, ec);
        if (ec)
          throw std::runtime_error("cannot copy " + path.string() + " to " + tmp.string() + ": " +
                                   ec.message());
      },
      [&](const std::filesystem::path& tmp) {
        H5::H5File file(tmp.string(), H5F_ACC_RDWR);
        const H5::Group root = file.openGroup("/");
        if (h5::GetAttrText(root, "format", path.string()) != kStudyFileFormat)
          throw std::runtime_error(path.string() + " is not a hoofimpact study file");
        if (h5::PathExists(root, group)) root.unlink(group);
        const H5::Group g = h5::MakeGroup(root, group, description);
        for (std::size_t i = 0; i < tables.size(); ++i) {
          WriteTable(g, tables[i]);
          if (after_table) after_table(i);
        }
        for (const auto& [link, target] : soft_links) {
          if (h5::PathExists(root, link)) root.unlink(link);
          if (H5Lcreate_soft(target.c_str(), root.getId(), link.c_str(), H5P_DEFAULT, H5P_DEFAULT) <
              0)
            throw std::runtime_error(path.string() + ": cannot link " + link + " to " + target);
        }
        file.flush(H5F_SCOPE_GLOBAL);
      });
}

// ------------------------------------------------------------------------------------------
// Reading
// ------------------------------------------------------------------------------------------

bool HasGroup(const std::filesystem::path& path, const std::string& group_path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    return h5::PathExists(file.openGroup("/"), group_path);
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
}

Table ReadTable(const std::filesystem::path& path, const std::string& table_path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  const std::string where = path.string() + ":" + table_path;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    if (!h5::PathExists(file.openGroup("/"), table_path))
      throw std::runtime_error(where + " does not exist");
    const H5::Group g = file.openGroup(table_path);
    Table t;
    t.name = table_path.substr(table_path.find_first_not_of('/'));
    t.description = g.attrExists("description") ? h5::GetAttrText(g, "description", where) : "";
    for (const std::string& c : h5::GetAttrTexts(g, "columns", where))
      t.columns.push_back(ReadColumn(g, c, where));
    t.Validate();
    return t;
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
}

}  // namespace hoof::studyfile
