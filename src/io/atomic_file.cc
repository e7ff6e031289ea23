#include "io/atomic_file.h"

#include "io/interrupt.h"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>

#include <signal.h>
#include <unistd.h>

namespace hoof::io {

std::filesystem::path TemporaryPathFor(const std::filesystem::path& path) {
  static std::atomic<unsigned long> counter{0};
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  TrackTemporary(tmp);  // an interrupt removes it unless it was committed
  return tmp;
}

void CreateFolder(const std::filesystem::path& dir) {
  const CreatingTemporary creating;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create directory " + dir.string() + ": " + ec.message());
}

void CommitTemporary(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  const CreatingTemporary creating;  // `path` may itself be a temporary (run's study file)
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    std::filesystem::remove(temporary, ec);
    UntrackTemporary(temporary);
    throw std::runtime_error("cannot write " + path.string() +
                             ": it is a folder; give a file name");
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    const std::string why = ec.message();  // before remove() overwrites ec ("Success")
    std::filesystem::remove(temporary, ec);
    UntrackTemporary(temporary);
    throw std::runtime_error("cannot move " + temporary.string() + " to " + path.string() + ": " +
                             why);
  }
  UntrackTemporary(temporary);
}

void WriteFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write) {
  std::optional<CreatingTemporary> creating(std::in_place);  // until the temporary is open
  if (path.has_parent_path()) CreateFolder(path.parent_path());
  const std::filesystem::path tmp = TemporaryPathFor(path);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    creating.reset();
    if (!out) throw std::runtime_error("cannot open " + tmp.string() + " for writing");
    write(out);
    out.flush();
    if (!out) throw std::runtime_error("write failed for " + path.string());
    out.close();
    if (out.fail()) throw std::runtime_error("closing failed for " + path.string());
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    UntrackTemporary(tmp);
    throw;
  }
  CommitTemporary(tmp, path);
}

void WriteTextAtomically(const std::filesystem::path& path, std::string_view content) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << content; });
}

namespace {

/// The process id in a name holding ".tmp-<pid>-<n>", or 0.
long TemporaryOwner(const std::string& name) {
  for (std::size_t at = name.find(".tmp-"); at != std::string::npos;
       at = name.find(".tmp-", at + 1)) {
    std::size_t i = at + 5, digits = 0;
    long pid = 0;
    while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i])) && digits < 10)
      pid = pid * 10 + (name[i++] - '0'), ++digits;
    if (digits == 0 || i >= name.size() || name[i] != '-') continue;
    if (i + 1 < name.size() && std::isdigit(static_cast<unsigned char>(name[i + 1]))) return pid;
  }
  return 0;
}

}  // namespace

int RemoveStaleTemporaries(const std::filesystem::path& dir,
                           const std::function<bool(const std::string&)>& ours) {
  int removed = 0;
  std::error_code ec;
  std::filesystem::directory_iterator it(dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (ours && !ours(name)) continue;
    const long pid = TemporaryOwner(name);
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH)
      continue;  // alive, or not ours to judge
    std::error_code rm;
    if (std::filesystem::remove_all(it->path(), rm) > 0 && !rm) ++removed;
  }
  return removed;
}

}  // namespace hoof::io
