#pragma once
/// @file
/// Helpers shared by the study file's translation units (internal to hoof::study_file):
/// atomic writes, HDF5 errors that name the file, the format check.
#include <H5Cpp.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "studyfile/study_file.h"

namespace hoof::studyfile::internal {

/// `parts` joined with `separator`.
std::string Join(const std::vector<std::string>& parts, const std::string& separator);

/// Throws std::runtime_error naming `path` for an HDF5 exception (which is no std::exception).
[[noreturn]] void RethrowHdf5(const H5::Exception& e, const std::filesystem::path& path);

/// Runs `write` on a temporary file beside `path` and renames it over `path`; removes the
/// temporary file on any failure. `prepare(tmp)` makes the temporary file (copy or nothing).
void AtomicHdf5(const std::filesystem::path& path,
                const std::function<void(const std::filesystem::path&)>& prepare,
                const std::function<void(const std::filesystem::path&)>& write);

/// Writes `table` as a group below `parent`: one 1-D dataset per column, and the attributes
/// description, columns and rows (tables.cc).
void WriteTable(const H5::Group& parent, const Table& table);

/// Throws std::runtime_error naming the file when its root attribute `format` is not ours.
void CheckFormat(const H5::Group& root, const std::filesystem::path& path);

/// The text column `name` of `t`; throws naming the table and the column otherwise.
std::vector<std::string> CheckedStrings(const Table& t, const std::string& name);

}  // namespace hoof::studyfile::internal
