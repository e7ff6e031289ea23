#pragma once
/// @file
/// The one JSON envelope every `hoofimpact <command> --json` prints on stdout (docs/cli.md,
/// "JSON output"):
///
///     {"format": "hoofimpact", "format_version": 1, "version": "0.1.0", "command": "analyze",
///      "success": true, "exit_code": 0, "results": {...}, "warnings": [...], "errors": [...]}
///
/// `results` is always an object (null when the command failed before it had any); its keys are
/// the names of the CSV columns and HDF5 datasets (docs/hdf5-schema.md). An error is
/// {"message": ...} with, where known, "option" (as the user typed it), "file", "trial" or
/// "field". `success` is `exit_code == 0`. Numbers keep full precision; NaN and infinities are
/// null.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace hoof::compare {
struct SurfaceModel;
}  // namespace hoof::compare
namespace hoof::report {
struct HtmlReportSummary;
}  // namespace hoof::report

namespace hoof::cli {

/// The program's version, as `--version` prints it and the envelope records it.
inline constexpr const char* kVersion = "0.1.0";

/// The envelope's format version: raised whenever a key of the envelope or of a command's
/// `results` changes meaning or goes away (adding a key does not raise it).
inline constexpr int kJsonFormatVersion = 1;

/// One error of the envelope's `errors`.
struct JsonError {
  std::string message;
  std::string option;  ///< the command-line option it concerns, e.g. "--angle-deg"
  std::string file;    ///< the file it concerns
  std::string trial;   ///< the trial id it concerns
  std::string field;   ///< the field (column, key) of the file it concerns
};

/// The error as JSON: "message" and only the keys that are set.
nlohmann::json ErrorJson(const JsonError& error);

/// An error from a message as the program words them: "--opt: why" names an option (CLI11's
/// ValidationError), "-o: why" too; "path/file.h5: why" or "file.csv:12: why" names a file
/// (the text before the first ": " when it has no space and holds a '/' or a '.').
JsonError ErrorFromMessage(const std::string& message);

/// The envelope of `command`: success is exit_code == 0.
nlohmann::json Envelope(const std::string& command, int exit_code, nlohmann::json results,
                        const std::vector<JsonError>& errors = {},
                        const std::vector<std::string>& warnings = {});

/// A surface's contact model with the column names of /comparison/surfaces.
nlohmann::json SurfaceModelJson(const compare::SurfaceModel& model);

/// The report written: output, bytes, trials, figures, replays, discovery, notes.
nlohmann::json ReportJson(const report::HtmlReportSummary& summary);

/// Prints the envelope on stdout (indented, one trailing newline).
void PrintEnvelope(const std::string& command, int exit_code, nlohmann::json results,
                   const std::vector<JsonError>& errors = {},
                   const std::vector<std::string>& warnings = {});

/// Adds `--json` to `cmd` (the same help everywhere).
CLI::Option* AddJsonFlag(CLI::App* cmd, bool& json);

/// The subcommand of the command line when its arguments hold `--json` (before a `--`), else
/// empty: main() prints an envelope for an error even when parsing failed.
std::string JsonCommandOf(int argc, const char* const* argv, const CLI::App& app);

}  // namespace hoof::cli
