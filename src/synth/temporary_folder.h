#pragma once
/// @file
/// An output folder written under a temporary name beside its target and renamed into place
/// when complete, so that a crash or an interrupt never leaves half a trial or clip.

#include <filesystem>

namespace hoof::synth {

/// A folder written under a temporary name (".<name>.tmp-<pid>-<n>" beside the target, which
/// an interrupt removes: io/interrupt.h) and renamed into place by Commit(). Destroyed before
/// Commit(), it removes the temporary.
class TemporaryFolder {
 public:
  /// Creates the temporary, with a frames/ folder inside when `frames`. Throws
  /// std::runtime_error naming the parent folder when it cannot.
  TemporaryFolder(const std::filesystem::path& target, bool frames);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  /// The temporary folder to write into.
  const std::filesystem::path& path() const { return temp_; }
  /// Renames the temporary to the target. An existing target is replaced only when `overwrite`;
  /// otherwise, and when a rename fails, std::runtime_error names it.
  void Commit(bool overwrite);

 private:
  std::filesystem::path target_, temp_;
  bool committed_ = false;
};

}  // namespace hoof::synth
