#include "synth/temporary_folder.h"

#include <atomic>
#include <stdexcept>
#include <string>
#include <system_error>

#include <unistd.h>

#include "io/interrupt.h"

namespace hoof::synth {
namespace fs = std::filesystem;

TemporaryFolder::TemporaryFolder(const fs::path& target, bool frames) : target_(target) {
  static std::atomic<int> counter{0};
  std::string name = ".";
  name.append(target.filename().string());
  name.append(".tmp-").append(std::to_string(::getpid()));
  name.append("-").append(std::to_string(counter++));
  temp_ = target.parent_path() / name;
  const io::CreatingTemporary creating;
  io::TrackTemporary(temp_);  // an interrupt removes it
  std::error_code ec;
  fs::create_directories(frames ? temp_ / "frames" : temp_, ec);
  if (ec)
    throw std::runtime_error("cannot create output folder '" + temp_.parent_path().string() +
                             "': " + ec.message());
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ec;
  if (!committed_) fs::remove_all(temp_, ec);
  io::UntrackTemporary(temp_);
}

void TemporaryFolder::Commit(bool overwrite) {
  std::error_code ec;
  fs::path trash;
  if (fs::exists(target_)) {
    if (!overwrite) throw std::runtime_error("output folder '" + target_.string() + "' exists");
    trash = temp_.string() + ".old";
    fs::rename(target_, trash, ec);
    if (ec) throw std::runtime_error("cannot replace '" + target_.string() + "': " + ec.message());
  }
  fs::rename(temp_, target_, ec);
  if (ec)
    throw std::runtime_error("cannot rename '" + temp_.string() + "' to '" + target_.string() +
                             "': " + ec.message());
  committed_ = true;
  if (!trash.empty()) fs::remove_all(trash, ec);
}

}  // namespace hoof::synth
