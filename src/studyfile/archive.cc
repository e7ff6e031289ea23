#include "studyfile/archive.h"

namespace hoof::studyfile::internal {

std::string ShapeText(const std::vector<hsize_t>& dims) {
  std::string out = "[";
  for (std::size_t i = 0; i < dims.size(); ++i) out += (i ? ", " : "") + std::to_string(dims[i]);
  return out + "]";
}

GroupReader::GroupReader(const H5::Group& group, std::string where)
    : group_(group), where_(std::move(where)) {}

GroupReader GroupReader::Group(const std::string& name) const {
  if (!Has(name)) throw std::runtime_error(Item(name) + " does not exist");
  if (group_.childObjType(name) != H5O_TYPE_GROUP)
    throw std::runtime_error(Item(name) + " is not a group");
  return GroupReader(group_.openGroup(name), Item(name));
}

hsize_t GroupReader::Length(const std::string& name) const {
  const std::vector<hsize_t> shape = h5::Shape(Open(name));
  if (shape.size() != 1)
    throw std::runtime_error(Item(name) + " has shape " + ShapeText(shape) +
                             ", expected one dimension");
  return shape[0];
}

std::vector<double> GroupReader::Doubles(const std::string& name,
                                         const std::vector<hsize_t>& dims) const {
  return h5::ReadDoubles(Open(name, dims), Item(name));
}

Eigen::Vector2d GroupReader::Vec2(const std::string& name) const {
  const std::vector<double> v = Doubles(name, {2});
  return {v[0], v[1]};
}

std::vector<std::int64_t> GroupReader::Integers(const std::string& name,
                                                const std::vector<hsize_t>& dims) const {
  return h5::ReadIntegers(Open(name, dims), Item(name));
}

int GroupReader::Int(const std::string& name) const {
  const std::int64_t v = Integers(name, {})[0];
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    throw std::runtime_error(Item(name) + " = " + std::to_string(v) + " is out of range");
  return static_cast<int>(v);
}

std::vector<std::string> GroupReader::Texts(const std::string& name,
                                            const std::vector<hsize_t>& dims) const {
  return h5::ReadTexts(Open(name, dims), Item(name));
}

H5::DataSet GroupReader::Open(const std::string& name) const {
  if (!Has(name)) throw std::runtime_error(Item(name) + " does not exist");
  if (group_.childObjType(name) != H5O_TYPE_DATASET)
    throw std::runtime_error(Item(name) + " is not a dataset");
  return group_.openDataSet(name);
}

H5::DataSet GroupReader::Open(const std::string& name, const std::vector<hsize_t>& dims) const {
  H5::DataSet d = Open(name);
  const std::vector<hsize_t> shape = h5::Shape(d);
  if (shape != dims)
    throw std::runtime_error(Item(name) + " has shape " + ShapeText(shape) + ", expected " +
                             ShapeText(dims));
  return d;
}

}  // namespace hoof::studyfile::internal
