#include "studyfile/file_util.h"

#include <stdexcept>
#include <system_error>

#include "io/atomic_file.h"
#include "io/interrupt.h"
#include "studyfile/hdf5_util.h"

namespace hoof::studyfile::internal {

std::string Join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
  return out;
}

[[noreturn]] void RethrowHdf5(const H5::Exception& e, const std::filesystem::path& path) {
  // The commonest cause first: a file that is not HDF5 at all (HDF5 only says "H5Fopen failed").
  if (std::filesystem::is_regular_file(path) && H5Fis_hdf5(path.string().c_str()) == 0)
    throw std::runtime_error(path.string() +
                             " is not an HDF5 file (study files are written by hoofimpact "
                             "analyze and hoofimpact run)");
  // A file with HDF5's signature that does not open: most often one cut short by a copy or a
  // killed writer (hoofimpact itself only ever renames complete files into place).
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (e.getFuncName().find("H5File") != std::string::npos)
    throw std::runtime_error(path.string() +
                             ": cannot be opened: the HDF5 file is damaged or cut short (" +
                             (ec ? std::string("size unknown") : std::to_string(bytes) + " bytes") +
                             "); write it again with hoofimpact analyze or run");
  throw std::runtime_error(path.string() + ": cannot be read, the HDF5 file is damaged (in " +
                           e.getFuncName() + ": " + e.getDetailMsg() + ")");
}

void AtomicHdf5(const std::filesystem::path& path,
                const std::function<void(const std::filesystem::path&)>& prepare,
                const std::function<void(const std::filesystem::path&)>& write) {
  H5::Exception::dontPrint();
  // Held while the temporary is made and written (HDF5 creates it inside `write`): an interrupt
  // waits for it rather than leave one made after its removal.
  const io::CreatingTemporary creating;
  if (path.has_parent_path()) io::CreateFolder(path.parent_path());
  const std::filesystem::path tmp = io::TemporaryPathFor(path);
  try {
    try {
      prepare(tmp);
      write(tmp);  // every H5 object is closed when this returns or throws
    } catch (const H5::Exception& e) {
      RethrowHdf5(e, path);
    }
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  io::CommitTemporary(tmp, path);
}

void CheckFormat(const H5::Group& root, const std::filesystem::path& path) {
  const std::string format = h5::GetAttrText(root, "format", path.string());
  if (format != kStudyFileFormat)
    throw std::runtime_error(path.string() + ": format \"" + format + "\", expected \"" +
                             kStudyFileFormat + "\"");
}

std::vector<std::string> CheckedStrings(const Table& t, const std::string& name) {
  const Column& c = t.Get(name);
  if (const auto* v = std::get_if<std::vector<std::string>>(&c.values)) return *v;
  throw std::runtime_error(t.name + "/" + name + " is not text");
}

}  // namespace hoof::studyfile::internal
