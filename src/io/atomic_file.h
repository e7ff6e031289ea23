#pragma once
/// @file
/// Writing output files so that a crash never leaves a half-written file: the content goes to a
/// temporary file beside the target, which is renamed over the target only when complete.

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>

namespace hoof::io {

/// Calls `write` with a stream onto a temporary file in the target's directory, flushes it and
/// renames it to `path`. On any failure the temporary file is removed, `path` is left as it
/// was, and std::runtime_error names the file. Creates missing parent directories.
void WriteFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write);

/// Writes `content` to `path` atomically (see WriteFileAtomically).
void WriteTextAtomically(const std::filesystem::path& path, std::string_view content);

/// A temporary path beside `path` (same directory, so a rename is atomic), unique per process
/// and call. Callers that write through a library (HDF5, OpenCV) write here, then call
/// CommitTemporary().
std::filesystem::path TemporaryPathFor(const std::filesystem::path& path);

/// Creates `dir` and its missing parents while holding a CreatingTemporary (interrupt.h): `dir`
/// may be, or lie inside, a temporary folder that an interrupt removes, and a folder made again
/// after that would be left behind. Throws std::runtime_error naming the folder.
void CreateFolder(const std::filesystem::path& dir);

/// Renames `temporary` over `path`; on failure removes `temporary` and throws
/// std::runtime_error naming both.
void CommitTemporary(const std::filesystem::path& temporary, const std::filesystem::path& path);

/// Removes from `dir` (not its sub-folders) the temporaries that a killed process left: files and
/// folders whose name holds ".tmp-<pid>-<n>" (TemporaryPathFor's, and the renderer's
/// ".<name>.tmp-<pid>-<n>" folders) for a process id that no longer runs. Another process's
/// live temporaries, and every other name, are left alone. With `ours`, only names it accepts
/// (a folder the program does not own, such as the one a study file is written into, holds
/// other programs' files). Returns how many were removed; never throws.
int RemoveStaleTemporaries(const std::filesystem::path& dir,
                           const std::function<bool(const std::string& name)>& ours = {});

}  // namespace hoof::io
