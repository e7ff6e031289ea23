#pragma once
/// @file
/// Archives that visit a persisted struct's fields (internal to hoof::study_file). A struct's
/// fields are declared once, in a Serialize() function of studyfile/schema.h that names each
/// field with its dataset name, units and description; H5Writer writes them as datasets of one
/// group and H5Reader reads them back with their shapes checked. The pattern is Drake's
/// `Serialize(Archive*)`: the same list of fields drives both directions, so a field cannot be
/// written under one name and read under another.
///
/// Each method takes the field by reference. A writer is given the struct as const and reads
/// from it; a reader is given it mutable and fills it. Serialize() is a template on both the
/// archive and the struct's constness, so one function serves both.
#include <H5Cpp.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "studyfile/hdf5_util.h"

namespace hoof::studyfile::internal {

/// "[2, 3]": a dataset's shape in an error message.
std::string ShapeText(const std::vector<hsize_t>& dims);

/// The datasets of one group, read with their shapes checked. `where` is the file and the
/// group ("study.h5:/trials/x"); every error names it and the item.
class GroupReader {
 public:
  GroupReader(const H5::Group& group, std::string where);

  const std::string& where() const { return where_; }
  bool Has(const std::string& name) const { return group_.nameExists(name); }
  GroupReader Group(const std::string& name) const;
  /// Length of the 1-D dataset `name`.
  hsize_t Length(const std::string& name) const;
  std::vector<double> Doubles(const std::string& name, const std::vector<hsize_t>& dims) const;
  double Scalar(const std::string& name) const { return Doubles(name, {})[0]; }
  Eigen::Vector2d Vec2(const std::string& name) const;
  std::vector<std::int64_t> Integers(const std::string& name,
                                     const std::vector<hsize_t>& dims) const;
  /// A scalar integer that fits an int.
  int Int(const std::string& name) const;
  bool Bool(const std::string& name) const { return Integers(name, {})[0] != 0; }
  std::vector<std::string> Texts(const std::string& name, const std::vector<hsize_t>& dims) const;
  std::string Text(const std::string& name) const { return Texts(name, {})[0]; }
  /// A 1-D text dataset of any length.
  std::vector<std::string> TextList(const std::string& name) const {
    return Texts(name, {Length(name)});
  }
  /// "where/name", for errors.
  std::string Item(const std::string& name) const { return where_ + "/" + name; }

 private:
  H5::DataSet Open(const std::string& name) const;
  H5::DataSet Open(const std::string& name, const std::vector<hsize_t>& dims) const;

  H5::Group group_;
  std::string where_;
};

/// The text of an enum value and back, for a field stored as text.
template <class Enum, std::size_t N>
using EnumNames = std::array<std::pair<Enum, const char*>, N>;

/// Writes each visited field as one dataset of `group`, with its units and description.
class H5Writer {
 public:
  static constexpr bool kWriting = true;
  explicit H5Writer(H5::Group group) : g_(std::move(group)) {}

  void Number(const std::string& name, double v, const std::string& units,
              const std::string& description) {
    h5::Scalar(g_, name, v, units, description);
  }
  /// A number whose "not measured" is std::nullopt in memory and NaN in the file.
  void MaybeNumber(const std::string& name, const std::optional<double>& v,
                   const std::string& units, const std::string& description) {
    h5::Scalar(g_, name, v.value_or(core::kNaN), units, description);
  }
  /// A number whose "not measured" is 0 in memory and NaN in the file.
  void NumberZeroUnmeasured(const std::string& name, double v, const std::string& units,
                            const std::string& description) {
    h5::Scalar(g_, name, v == 0.0 ? core::kNaN : v, units, description);
  }
  void Integer(const std::string& name, int v, const std::string& units,
               const std::string& description) {
    h5::Integers(g_, name, {v}, {}, units, description);
  }
  void Flag(const std::string& name, bool v, const std::string& description) {
    h5::Bools(g_, name, {v ? std::uint8_t{1} : std::uint8_t{0}}, {}, description);
  }
  void Text(const std::string& name, const std::string& v, const std::string& description) {
    h5::Text(g_, name, v, description);
  }
  void Path(const std::string& name, const std::filesystem::path& v,
            const std::string& description) {
    h5::Text(g_, name, v.string(), description);
  }
  /// A text or a number that a file written before the field existed lacks (the reader then
  /// keeps the value it was given).
  void LaterText(const std::string& name, const std::string& v, const std::string& description) {
    Text(name, v, description);
  }
  void LaterNumber(const std::string& name, double v, const std::string& units,
                   const std::string& description) {
    Number(name, v, units, description);
  }
  void TextList(const std::string& name, const std::vector<std::string>& v,
                const std::string& description) {
    h5::Texts(g_, name, v, {v.size()}, description);
  }
  void Vec2(const std::string& name, const Eigen::Vector2d& v, const std::string& units,
            const std::string& description) {
    h5::Vec2(g_, name, v, units, description);
  }
  /// Two numbers stored as one dataset of shape [2] (an interval: low, high).
  void Pair(const std::string& name, double first, double second, const std::string& units,
            const std::string& description) {
    h5::Doubles(g_, name, {first, second}, {2}, units, description);
  }
  /// A 2x2 matrix, shape [2, 2], row-major.
  void Matrix2(const std::string& name, const Eigen::Matrix2d& m, const std::string& units,
               const std::string& description) {
    h5::Doubles(g_, name, {m(0, 0), m(0, 1), m(1, 0), m(1, 1)}, {2, 2}, units, description);
  }
  /// N numbers of shape `dims` (row-major), written only when present.
  template <std::size_t N>
  void MaybeArray(const std::string& name, const std::optional<std::array<double, N>>& v,
                  const std::vector<hsize_t>& dims, const std::string& units,
                  const std::string& description) {
    if (v)
      h5::Doubles(g_, name, std::vector<double>(v->begin(), v->end()), dims, units, description);
  }
  /// N points of shape [N, 2], written only when present.
  template <std::size_t N>
  void MaybePoints(const std::string& name, const std::optional<std::array<Eigen::Vector2d, N>>& v,
                   const std::string& units, const std::string& description) {
    if (!v) return;
    std::vector<double> flat;
    for (const Eigen::Vector2d& p : *v) {
      flat.push_back(p.x());
      flat.push_back(p.y());
    }
    h5::Doubles(g_, name, flat, {N, 2}, units, description);
  }
  /// Named points: their names as one text dataset, their (x, y) as another of shape [n, 2].
  void NamedPoints(const std::string& names_name, const std::string& points_name,
                   const std::vector<std::pair<std::string, Eigen::Vector2d>>& v,
                   const std::string& units, const std::string& names_description,
                   const std::string& points_description) {
    std::vector<std::string> names;
    std::vector<double> p;
    for (const auto& [name, point] : v) {
      names.push_back(name);
      p.push_back(point.x());
      p.push_back(point.y());
    }
    h5::Texts(g_, names_name, names, {names.size()}, names_description);
    h5::Doubles(g_, points_name, p, {names.size(), 2}, units, points_description);
  }
  /// An enum stored as its text.
  template <class Enum, std::size_t N>
  void Choice(const std::string& name, Enum v, const EnumNames<Enum, N>& names,
              const std::string& description) {
    for (const auto& [value, text] : names)
      if (value == v) return h5::Text(g_, name, text, description);
    throw std::logic_error(name + ": an enum value without a name");
  }
  /// An enum stored as its text, which a file written before the field existed lacks (the
  /// reader then keeps the value it was given).
  template <class Enum, std::size_t N>
  void LaterChoice(const std::string& name, Enum v, const EnumNames<Enum, N>& names,
                   const std::string& description) {
    Choice(name, v, names, description);
  }

 protected:
  /// The group written, for an archive that adds fields of other kinds (FramesWriter).
  const H5::Group& group() const { return g_; }

 private:
  H5::Group g_;
};

/// Reads each visited field from one group, with its shape checked; an error names the file,
/// the group and the field.
class H5Reader {
 public:
  static constexpr bool kWriting = false;
  explicit H5Reader(GroupReader group) : g_(std::move(group)) {}

  void Number(const std::string& name, double& v, const std::string& /*units*/,
              const std::string& /*description*/) const {
    v = g_.Scalar(name);
  }
  void MaybeNumber(const std::string& name, std::optional<double>& v, const std::string& /*units*/,
                   const std::string& /*description*/) const {
    const double x = g_.Scalar(name);
    v = std::isnan(x) ? std::nullopt : std::optional<double>(x);
  }
  void NumberZeroUnmeasured(const std::string& name, double& v, const std::string& /*units*/,
                            const std::string& /*description*/) const {
    const double x = g_.Scalar(name);
    v = std::isnan(x) ? 0.0 : x;
  }
  void Integer(const std::string& name, int& v, const std::string& /*units*/,
               const std::string& /*description*/) const {
    v = g_.Int(name);
  }
  void Flag(const std::string& name, bool& v, const std::string& /*description*/) const {
    v = g_.Bool(name);
  }
  void Text(const std::string& name, std::string& v, const std::string& /*description*/) const {
    v = g_.Text(name);
  }
  void Path(const std::string& name, std::filesystem::path& v,
            const std::string& /*description*/) const {
    v = g_.Text(name);
  }
  void LaterText(const std::string& name, std::string& v, const std::string& description) const {
    if (g_.Has(name)) Text(name, v, description);
  }
  void LaterNumber(const std::string& name, double& v, const std::string& units,
                   const std::string& description) const {
    if (g_.Has(name)) Number(name, v, units, description);
  }
  void TextList(const std::string& name, std::vector<std::string>& v,
                const std::string& /*description*/) const {
    v = g_.TextList(name);
  }
  void Vec2(const std::string& name, Eigen::Vector2d& v, const std::string& /*units*/,
            const std::string& /*description*/) const {
    v = g_.Vec2(name);
  }
  void Pair(const std::string& name, double& first, double& second, const std::string& /*units*/,
            const std::string& /*description*/) const {
    const std::vector<double> v = g_.Doubles(name, {2});
    first = v[0];
    second = v[1];
  }
  void Matrix2(const std::string& name, Eigen::Matrix2d& m, const std::string& /*units*/,
               const std::string& /*description*/) const {
    const std::vector<double> v = g_.Doubles(name, {2, 2});
    m << v[0], v[1], v[2], v[3];
  }
  template <std::size_t N>
  void MaybeArray(const std::string& name, std::optional<std::array<double, N>>& v,
                  const std::vector<hsize_t>& dims, const std::string& /*units*/,
                  const std::string& /*description*/) const {
    if (!g_.Has(name)) return v.reset();
    const std::vector<double> x = g_.Doubles(name, dims);
    if (x.size() != N)
      throw std::runtime_error(g_.Item(name) + " does not hold " + std::to_string(N) + " numbers");
    v.emplace();
    std::copy(x.begin(), x.end(), v->begin());
  }
  template <std::size_t N>
  void MaybePoints(const std::string& name, std::optional<std::array<Eigen::Vector2d, N>>& v,
                   const std::string& /*units*/, const std::string& /*description*/) const {
    if (!g_.Has(name)) return v.reset();
    const std::vector<double> x = g_.Doubles(name, {N, 2});
    v.emplace();
    for (std::size_t i = 0; i < N; ++i) (*v)[i] = {x[2 * i], x[2 * i + 1]};
  }
  void NamedPoints(const std::string& names_name, const std::string& points_name,
                   std::vector<std::pair<std::string, Eigen::Vector2d>>& v,
                   const std::string& /*units*/, const std::string& /*names_description*/,
                   const std::string& /*points_description*/) const {
    const std::vector<std::string> names = g_.TextList(names_name);
    const std::vector<double> p = g_.Doubles(points_name, {names.size(), 2});
    v.clear();
    for (std::size_t i = 0; i < names.size(); ++i)
      v.emplace_back(names[i], Eigen::Vector2d(p[2 * i], p[2 * i + 1]));
  }
  template <class Enum, std::size_t N>
  void Choice(const std::string& name, Enum& v, const EnumNames<Enum, N>& names,
              const std::string& /*description*/) const {
    const std::string text = g_.Text(name);
    std::string choices;
    for (const auto& [value, value_text] : names) {
      if (text == value_text) {
        v = value;
        return;
      }
      choices += (choices.empty() ? "" : ", ") + std::string(value_text);
    }
    throw std::runtime_error(g_.Item(name) + " = \"" + text + "\" is none of " + choices);
  }
  template <class Enum, std::size_t N>
  void LaterChoice(const std::string& name, Enum& v, const EnumNames<Enum, N>& names,
                   const std::string& description) const {
    if (g_.Has(name)) Choice(name, v, names, description);
  }

 protected:
  /// The group read, for an archive that adds fields of other kinds (FramesReader).
  const GroupReader& group() const { return g_; }

 private:
  GroupReader g_;
};

}  // namespace hoof::studyfile::internal
