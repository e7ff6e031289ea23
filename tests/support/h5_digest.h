#pragma once
// Every dataset and attribute of an HDF5 file as text, read with the HDF5 C API and nothing of
// the project's own reader, so two study files can be compared whatever wrote them.
#include <hdf5.h>

#include <cstdio>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace hoof::testing {

/// One dataset or attribute: its numbers (integers and floats, as doubles) or its texts.
struct H5Value {
  bool is_text = false;
  std::vector<double> numbers;
  std::vector<std::string> texts;
};

/// Keyed "/group/dataset" for a dataset and "/group/dataset@name" for an attribute.
using H5Digest = std::map<std::string, H5Value>;

namespace internal {

inline H5Value ReadValue(hid_t obj, hid_t type, hid_t space, bool attribute) {
  H5Value v;
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n <= 0) return v;
  const H5T_class_t cls = H5Tget_class(type);
  if (cls == H5T_INTEGER || cls == H5T_FLOAT || cls == H5T_ENUM) {
    v.numbers.resize(static_cast<std::size_t>(n));
    if (attribute)
      H5Aread(obj, H5T_NATIVE_DOUBLE, v.numbers.data());
    else
      H5Dread(obj, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.numbers.data());
  } else if (cls == H5T_STRING) {
    v.is_text = true;
    if (H5Tis_variable_str(type) > 0) {
      std::vector<char*> raw(static_cast<std::size_t>(n), nullptr);
      const hid_t mem = H5Tcopy(H5T_C_S1);
      H5Tset_size(mem, H5T_VARIABLE);
      H5Tset_cset(mem, H5Tget_cset(type));  // UTF-8 strings convert to UTF-8 only
      if (attribute)
        H5Aread(obj, mem, raw.data());
      else
        H5Dread(obj, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data());
      for (char* s : raw) v.texts.emplace_back(s ? s : "");
      H5Dvlen_reclaim(mem, space, H5P_DEFAULT, raw.data());
      H5Tclose(mem);
    } else {
      const std::size_t size = H5Tget_size(type);
      std::vector<char> buf(size * static_cast<std::size_t>(n));
      if (attribute)
        H5Aread(obj, type, buf.data());
      else
        H5Dread(obj, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
      for (hssize_t i = 0; i < n; ++i) {
        std::string s(buf.data() + static_cast<std::size_t>(i) * size, size);
        s.erase(s.find_last_not_of('\0') + 1);
        v.texts.push_back(s);
      }
    }
  } else {
    v.is_text = true;
    v.texts.push_back("<type class " + std::to_string(static_cast<int>(cls)) + ">");
  }
  return v;
}

inline herr_t OnAttribute(hid_t loc, const char* name, const H5A_info_t*, void* data) {
  auto* out = static_cast<std::pair<H5Digest*, std::string>*>(data);
  const hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  const hid_t type = H5Aget_type(a), space = H5Aget_space(a);
  (*out->first)[out->second + "@" + name] = ReadValue(a, type, space, true);
  H5Sclose(space);
  H5Tclose(type);
  H5Aclose(a);
  return 0;
}

inline herr_t OnObject(hid_t root, const char* name, const H5O_info_t* info, void* data) {
  auto* digest = static_cast<H5Digest*>(data);
  std::string path = "/";
  if (std::string_view(name) != ".") path.append(name);
  const hid_t obj = H5Oopen(root, name, H5P_DEFAULT);
  if (info->type == H5O_TYPE_DATASET) {
    const hid_t type = H5Dget_type(obj), space = H5Dget_space(obj);
    (*digest)[path] = ReadValue(obj, type, space, false);
    H5Sclose(space);
    H5Tclose(type);
  }
  std::pair<H5Digest*, std::string> attr{digest, path};
  H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, nullptr, OnAttribute, &attr);
  H5Oclose(obj);
  return 0;
}

}  // namespace internal

/// Reads every dataset and attribute of `path`; empty when the file cannot be opened.
inline H5Digest DigestHdf5(const std::string& path) {
  H5Digest digest;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return digest;
  H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_INC, internal::OnObject, &digest, H5O_INFO_BASIC);
  H5Fclose(file);
  return digest;
}

/// The digest as text, one line per key: "key\tN|T\tvalue\tvalue...", numbers with 17 digits.
inline std::string DigestText(const H5Digest& digest) {
  std::string out;
  char buf[64];
  for (const auto& [key, v] : digest) {
    out.append(key);
    out.append(v.is_text ? "\tT" : "\tN");
    if (v.is_text) {
      for (const auto& s : v.texts) {
        out.push_back('\t');
        for (char c : s) {
          if (c == '\n') {
            out.append("\\n");
          } else if (c == '\t') {
            out.append("\\t");
          } else {
            out.push_back(c);
          }
        }
      }
    } else {
      for (double x : v.numbers) {
        std::snprintf(buf, sizeof buf, "\t%.17g", x);
        out.append(buf);
      }
    }
    out.push_back('\n');
  }
  return out;
}

}  // namespace hoof::testing
