#include "io/atomic_file.h"

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include <unistd.h>

namespace hoof::io {

std::filesystem::path TemporaryPathFor(const std::filesystem::path& path) {
  static std::atomic<unsigned long> counter{0};
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return tmp;
}

void CommitTemporary(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    std::filesystem::remove(temporary, ec);
    throw std::runtime_error("cannot write " + path.string() + ": it is a folder; give a file name");
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    const std::string why = ec.message();  // before remove() overwrites ec ("Success")
    std::filesystem::remove(temporary, ec);
    throw std::runtime_error("cannot move " + temporary.string() + " to " + path.string() + ": " + why);
  }
}

void WriteFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write) {
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec)
      throw std::runtime_error("cannot create directory " + path.parent_path().string() + ": " +
                               ec.message());
  }
  const std::filesystem::path tmp = TemporaryPathFor(path);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open " + tmp.string() + " for writing");
    write(out);
    out.flush();
    if (!out) throw std::runtime_error("write failed for " + path.string());
    out.close();
    if (out.fail()) throw std::runtime_error("closing failed for " + path.string());
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  CommitTemporary(tmp, path);
}

void WriteTextAtomically(const std::filesystem::path& path, std::string_view content) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << content; });
}

}  // namespace hoof::io
