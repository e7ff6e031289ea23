#pragma once
/// @file
/// Small helpers over the HDF5 C++ API used by the study file's translation units (internal to
/// hoof::study_file): datasets that always carry `units` and `description` attributes,
/// variable-length UTF-8 text, and readers that name the dataset when it is missing or has the
/// wrong shape.

#include <H5Cpp.h>

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hoof::studyfile::h5 {

/// Variable-length UTF-8 string type.
H5::StrType TextType();

/// Sets (replaces) a scalar text attribute.
void SetAttr(const H5::H5Object& obj, const std::string& name, const std::string& value);
/// Sets (replaces) a 1-D text attribute.
void SetAttr(const H5::H5Object& obj, const std::string& name,
             const std::vector<std::string>& values);
/// Sets (replaces) a scalar integer attribute.
void SetAttr(const H5::H5Object& obj, const std::string& name, std::int64_t value);

/// Reads a scalar text attribute; `where` names the object in the error.
std::string GetAttrText(const H5::H5Object& obj, const std::string& name, const std::string& where);
/// Reads a 1-D text attribute.
std::vector<std::string> GetAttrTexts(const H5::H5Object& obj, const std::string& name,
                                      const std::string& where);

/// Whether the absolute or relative `path` exists below `loc`, checking each component (so a
/// missing intermediate group gives false, not an error).
bool PathExists(const H5::Group& loc, const std::string& path);

/// Creates a group, with its parents when `name` holds '/', and sets its description.
H5::Group MakeGroup(const H5::Group& parent, const std::string& name,
                    const std::string& description);

/// Doubles of shape `dims` (empty = scalar), row-major.
void Doubles(const H5::Group& g, const std::string& name, const std::vector<double>& data,
             const std::vector<hsize_t>& dims, const std::string& units,
             const std::string& description);
/// A scalar double.
void Scalar(const H5::Group& g, const std::string& name, double value, const std::string& units,
            const std::string& description);
/// A 2-vector, shape [2].
void Vec2(const H5::Group& g, const std::string& name, const Eigen::Vector2d& v,
          const std::string& units, const std::string& description);
/// 64-bit integers of shape `dims` (empty = scalar).
void Integers(const H5::Group& g, const std::string& name, const std::vector<std::int64_t>& data,
              const std::vector<hsize_t>& dims, const std::string& units,
              const std::string& description);
/// 32-bit integers of shape `dims`.
void Int32s(const H5::Group& g, const std::string& name, const std::vector<std::int32_t>& data,
            const std::vector<hsize_t>& dims, const std::string& units,
            const std::string& description);
/// Booleans as uint8 0/1 of shape `dims` (empty = scalar); units "".
void Bools(const H5::Group& g, const std::string& name, const std::vector<std::uint8_t>& data,
           const std::vector<hsize_t>& dims, const std::string& description);
/// Text of shape `dims` (empty = scalar); units "".
void Texts(const H5::Group& g, const std::string& name, const std::vector<std::string>& data,
           const std::vector<hsize_t>& dims, const std::string& description);
/// One text value (scalar dataset).
void Text(const H5::Group& g, const std::string& name, const std::string& value,
          const std::string& description);

/// Shape of a dataset.
std::vector<hsize_t> Shape(const H5::DataSet& d);
/// Reads any numeric dataset as doubles (row-major); `where` names it in errors.
std::vector<double> ReadDoubles(const H5::DataSet& d, const std::string& where);
/// Reads any integer dataset as int64.
std::vector<std::int64_t> ReadIntegers(const H5::DataSet& d, const std::string& where);
/// Reads a text dataset (variable- or fixed-length strings).
std::vector<std::string> ReadTexts(const H5::DataSet& d, const std::string& where);

}  // namespace hoof::studyfile::h5
