#include "studyfile/frame_archive.h"

#include <limits>
#include <stdexcept>

namespace hoof::studyfile::internal {

ElementWriter::Dataset& ElementWriter::Find(const std::string& name) {
  for (Dataset& d : datasets_)
    if (d.name == name) return d;
  throw std::logic_error("per-frame element visits \"" + name + "\", which it did not declare");
}

void ElementWriter::WriteDatasets(const H5::Group& group, const std::vector<hsize_t>& dims) const {
  for (const Dataset& d : datasets_) {
    std::vector<hsize_t> shape = dims;
    if (d.width != 1) shape.push_back(d.width);
    if (const auto* x = std::get_if<std::vector<double>>(&d.values))
      h5::Doubles(group, d.name, *x, shape, d.units, d.description);
    else if (const auto* b = std::get_if<std::vector<std::uint8_t>>(&d.values))
      h5::Bools(group, d.name, *b, shape, d.description);
    else if (const auto* i = std::get_if<std::vector<std::int32_t>>(&d.values))
      h5::Int32s(group, d.name, *i, shape, d.units, d.description);
    else
      h5::Texts(group, d.name, std::get<std::vector<std::string>>(d.values), shape, d.description);
  }
}

void ElementReader::Int32(const std::string& name, int& v, const std::string& /*units*/,
                          const std::string& /*description*/) {
  const std::vector<std::int64_t>* x = Integers(name);
  if (!x) return;
  const std::int64_t value = (*x)[i_];
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
    throw std::runtime_error(group_.Item(name) + "[" + std::to_string(i_) +
                             "] = " + std::to_string(value) + " is out of range");
  v = static_cast<int>(value);
}

const std::vector<double>* ElementReader::Doubles(const std::string& name, hsize_t width) {
  if (!loading_) return &doubles_.at(name);
  std::vector<hsize_t> shape = dims_;
  if (width != 1) shape.push_back(width);
  doubles_[name] = group_.Doubles(name, shape);
  return nullptr;
}

const std::vector<std::int64_t>* ElementReader::Integers(const std::string& name) {
  if (!loading_) return &integers_.at(name);
  integers_[name] = group_.Integers(name, dims_);
  return nullptr;
}

const std::vector<std::string>* ElementReader::Texts(const std::string& name) {
  if (!loading_) return &texts_.at(name);
  texts_[name] = group_.Texts(name, dims_);
  return nullptr;
}

void ElementReader::AssignPending() {
  for (const Pending& p : pending_)
    if (*p.present) *p.field = p.value;
  pending_.clear();
}

}  // namespace hoof::studyfile::internal
