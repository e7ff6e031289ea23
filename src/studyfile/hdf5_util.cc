#include "studyfile/hdf5_util.h"

#include <numeric>
#include <stdexcept>

namespace hoof::studyfile::h5 {
namespace {

H5::DataSpace Space(const std::vector<hsize_t>& dims) {
  if (dims.empty()) return H5::DataSpace(H5S_SCALAR);
  return H5::DataSpace(static_cast<int>(dims.size()), dims.data());
}

hsize_t Count(const std::vector<hsize_t>& dims) {
  return std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<hsize_t>());
}

void CheckCount(const std::string& name, std::size_t size, const std::vector<hsize_t>& dims) {
  if (size != Count(dims))
    throw std::logic_error("dataset " + name + ": " + std::to_string(size) +
                           " values for a shape of " + std::to_string(Count(dims)));
}

void Describe(const H5::DataSet& d, const std::string& units, const std::string& description) {
  SetAttr(d, "units", units);
  SetAttr(d, "description", description);
}

template <typename T>
void WriteNumeric(const H5::Group& g, const std::string& name, const std::vector<T>& data,
                  const std::vector<hsize_t>& dims, const H5::PredType& file_type,
                  const H5::PredType& memory_type, const std::string& units,
                  const std::string& description) {
  CheckCount(name, data.size(), dims);
  H5::DataSet d = g.createDataSet(name, file_type, Space(dims));
  if (!data.empty()) d.write(data.data(), memory_type);
  Describe(d, units, description);
}

}  // namespace

H5::StrType TextType() {
  H5::StrType t(H5::PredType::C_S1, H5T_VARIABLE);
  t.setCset(H5T_CSET_UTF8);
  return t;
}

void SetAttr(const H5::H5Object& obj, const std::string& name, const std::string& value) {
  if (obj.attrExists(name)) obj.removeAttr(name);
  const H5::StrType t = TextType();
  H5::Attribute a = obj.createAttribute(name, t, H5::DataSpace(H5S_SCALAR));
  a.write(t, value);
}

void SetAttr(const H5::H5Object& obj, const std::string& name,
             const std::vector<std::string>& values) {
  if (obj.attrExists(name)) obj.removeAttr(name);
  const H5::StrType t = TextType();
  const hsize_t n = values.size();
  H5::Attribute a = obj.createAttribute(name, t, H5::DataSpace(1, &n));
  std::vector<const char*> p;
  for (const auto& v : values) p.push_back(v.c_str());
  if (!p.empty()) a.write(t, p.data());
}

void SetAttr(const H5::H5Object& obj, const std::string& name, std::int64_t value) {
  if (obj.attrExists(name)) obj.removeAttr(name);
  H5::Attribute a = obj.createAttribute(name, H5::PredType::STD_I64LE, H5::DataSpace(H5S_SCALAR));
  a.write(H5::PredType::NATIVE_INT64, &value);
}

std::string GetAttrText(const H5::H5Object& obj, const std::string& name,
                        const std::string& where) {
  if (!obj.attrExists(name)) throw std::runtime_error(where + " has no attribute \"" + name + "\"");
  H5::Attribute a = obj.openAttribute(name);
  if (a.getTypeClass() != H5T_STRING)
    throw std::runtime_error(where + ": attribute \"" + name + "\" is not text");
  std::string value;
  a.read(a.getStrType(), value);
  return value;
}

std::vector<std::string> GetAttrTexts(const H5::H5Object& obj, const std::string& name,
                                      const std::string& where) {
  if (!obj.attrExists(name)) throw std::runtime_error(where + " has no attribute \"" + name + "\"");
  H5::Attribute a = obj.openAttribute(name);
  const H5::DataSpace space = a.getSpace();
  const auto n = static_cast<std::size_t>(space.getSimpleExtentNpoints());
  if (a.getTypeClass() != H5T_STRING || !a.getStrType().isVariableStr())
    throw std::runtime_error(where + ": attribute \"" + name + "\" is not variable-length text");
  std::vector<char*> p(n, nullptr);
  if (n > 0) a.read(TextType(), p.data());
  std::vector<std::string> out;
  for (char* s : p) out.emplace_back(s ? s : "");
  if (n > 0) H5::DataSet::vlenReclaim(p.data(), TextType(), space);
  return out;
}

bool PathExists(const H5::Group& loc, const std::string& path) {
  // Check "/a", then "/a/b", ...: H5Lexists fails when an intermediate group is missing.
  for (std::size_t end = path.find('/', 1);; end = path.find('/', end + 1)) {
    const std::string prefix = path.substr(0, end);
    if (!prefix.empty() && prefix != "/" && !loc.nameExists(prefix)) return false;
    if (end == std::string::npos) return true;
  }
}

H5::Group MakeGroup(const H5::Group& parent, const std::string& name,
                    const std::string& description) {
  H5::LinkCreatPropList lcpl;
  lcpl.setCreateIntermediateGroup(true);
  lcpl.setCharEncoding(H5T_CSET_UTF8);
  H5::Group g = parent.createGroup(name, lcpl);
  SetAttr(g, "description", description);
  return g;
}

void Doubles(const H5::Group& g, const std::string& name, const std::vector<double>& data,
             const std::vector<hsize_t>& dims, const std::string& units,
             const std::string& description) {
  WriteNumeric(g, name, data, dims, H5::PredType::IEEE_F64LE, H5::PredType::NATIVE_DOUBLE, units,
               description);
}

void Scalar(const H5::Group& g, const std::string& name, double value, const std::string& units,
            const std::string& description) {
  Doubles(g, name, {value}, {}, units, description);
}

void Vec2(const H5::Group& g, const std::string& name, const Eigen::Vector2d& v,
          const std::string& units, const std::string& description) {
  Doubles(g, name, {v.x(), v.y()}, {2}, units, description);
}

void Integers(const H5::Group& g, const std::string& name, const std::vector<std::int64_t>& data,
              const std::vector<hsize_t>& dims, const std::string& units,
              const std::string& description) {
  WriteNumeric(g, name, data, dims, H5::PredType::STD_I64LE, H5::PredType::NATIVE_INT64, units,
               description);
}

void Int32s(const H5::Group& g, const std::string& name, const std::vector<std::int32_t>& data,
            const std::vector<hsize_t>& dims, const std::string& units,
            const std::string& description) {
  WriteNumeric(g, name, data, dims, H5::PredType::STD_I32LE, H5::PredType::NATIVE_INT32, units,
               description);
}

void Bools(const H5::Group& g, const std::string& name, const std::vector<std::uint8_t>& data,
           const std::vector<hsize_t>& dims, const std::string& description) {
  WriteNumeric(g, name, data, dims, H5::PredType::STD_U8LE, H5::PredType::NATIVE_UINT8, "",
               description);
}

void Texts(const H5::Group& g, const std::string& name, const std::vector<std::string>& data,
           const std::vector<hsize_t>& dims, const std::string& description) {
  CheckCount(name, data.size(), dims);
  const H5::StrType t = TextType();
  H5::DataSet d = g.createDataSet(name, t, Space(dims));
  std::vector<const char*> p;
  for (const auto& s : data) p.push_back(s.c_str());
  if (!p.empty()) d.write(p.data(), t);
  Describe(d, "", description);
}

void Text(const H5::Group& g, const std::string& name, const std::string& value,
          const std::string& description) {
  Texts(g, name, {value}, {}, description);
}

std::vector<hsize_t> Shape(const H5::DataSet& d) {
  const H5::DataSpace space = d.getSpace();
  const int rank = space.getSimpleExtentNdims();
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0) space.getSimpleExtentDims(dims.data());
  return dims;
}

std::vector<double> ReadDoubles(const H5::DataSet& d, const std::string& where) {
  const H5T_class_t c = d.getTypeClass();
  if (c != H5T_FLOAT && c != H5T_INTEGER) throw std::runtime_error(where + " is not numeric");
  std::vector<double> out(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
  if (!out.empty()) d.read(out.data(), H5::PredType::NATIVE_DOUBLE);
  return out;
}

std::vector<std::int64_t> ReadIntegers(const H5::DataSet& d, const std::string& where) {
  if (d.getTypeClass() != H5T_INTEGER)
    throw std::runtime_error(where + " is not an integer dataset");
  std::vector<std::int64_t> out(static_cast<std::size_t>(d.getSpace().getSimpleExtentNpoints()));
  if (!out.empty()) d.read(out.data(), H5::PredType::NATIVE_INT64);
  return out;
}

std::vector<std::string> ReadTexts(const H5::DataSet& d, const std::string& where) {
  if (d.getTypeClass() != H5T_STRING) throw std::runtime_error(where + " is not text");
  const H5::DataSpace space = d.getSpace();
  const auto n = static_cast<std::size_t>(space.getSimpleExtentNpoints());
  const H5::StrType file_type = d.getStrType();
  std::vector<std::string> out;
  if (n == 0) return out;
  if (file_type.isVariableStr()) {
    const H5::StrType t = TextType();
    std::vector<char*> p(n, nullptr);
    d.read(p.data(), t);
    for (char* s : p) out.emplace_back(s ? s : "");
    H5::DataSet::vlenReclaim(p.data(), t, space);
  } else {
    const std::size_t size = file_type.getSize();
    std::vector<char> buf(n * size);
    d.read(buf.data(), file_type);
    for (std::size_t i = 0; i < n; ++i) {
      std::string s(buf.data() + i * size, size);
      s.erase(s.find_last_not_of(std::string("\0 ", 2)) + 1);
      out.push_back(s);
    }
  }
  return out;
}

}  // namespace hoof::studyfile::h5
