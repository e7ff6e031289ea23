// Reading the study file's /discovery group back (discovery/discovery_tables.h).
#include <cstdint>
#include <exception>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "discovery/discovery_schema.h"
#include "discovery/discovery_tables.h"
#include "studyfile/table_archive.h"

namespace hoof::discovery {
namespace {

using namespace schema;

// ---- reading ------------------------------------------------------------------------------

/// One table of the /discovery group, read with errors that name the file and the table.
class Reader {
 public:
  Reader(const std::filesystem::path& h5, const std::string& table)
      : h5_(h5), path_(std::string(kDiscoveryGroup) + "/" + table) {
    try {
      table_ = studyfile::ReadTable(h5, path_);
    } catch (const std::exception& e) {
      const std::string what = e.what();
      throw std::runtime_error(what.find(h5.string()) != std::string::npos
                                   ? what
                                   : h5.string() + ": table " + path_ + ": " + what);
    }
  }

  const Table& table() const { return table_; }
  /// "<file>: table <path>", how errors name the table.
  std::string where() const { return h5_.string() + ": table " + path_; }

 private:
  std::filesystem::path h5_;
  std::string path_;
  Table table_;
};

std::vector<StructureTest> ReadTests(const std::filesystem::path& h5, const std::string& table) {
  const Reader t(h5, table);
  return studyfile::TableReader::Read<StructureTest>(
      t.table(), t.where(), [](auto& a, StructureTest& s) { Serialize(a, s); });
}

std::vector<CandidateResult> ReadCandidates(const std::filesystem::path& h5,
                                            const std::string& table) {
  const Reader t(h5, table);
  return studyfile::TableReader::Read<CandidateResult>(
      t.table(), t.where(), [](auto& a, CandidateResult& c) { Serialize(a, c); });
}

/// Reads a ValuesTable and appends each row's value to the `values` of its owner (`owner`
/// column: the row of `owners`).
template <typename Owner>
void ReadValues(const std::filesystem::path& h5, const std::string& table, const std::string& owner,
                std::vector<Owner>& owners) {
  const Reader t(h5, table);
  const auto rows = studyfile::TableReader::Read<ValueRow>(
      t.table(), t.where(), [&](auto& a, ValueRow& r) { Serialize(a, r, owner, ""); });
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::int64_t row = rows[i].owner;
    if (row < 0 || static_cast<std::size_t>(row) >= owners.size())
      throw std::runtime_error(t.where() + ": column \"" + owner + "\" row " + std::to_string(i) +
                               ": " + std::to_string(row) + " is not a row of the " +
                               std::to_string(owners.size()) + " it refers to");
    owners[static_cast<std::size_t>(row)].values.push_back(rows[i].value);
  }
}

std::vector<GapTrial> ReadGap(const std::filesystem::path& h5, const std::string& table) {
  const Reader t(h5, table);
  return studyfile::TableReader::Read<GapTrial>(t.table(), t.where(),
                                                [](auto& a, GapTrial& g) { Serialize(a, g); });
}

}  // namespace

DiscoveryResult ReadDiscovery(const std::filesystem::path& h5) {
  DiscoveryResult r;
  std::int64_t rounds = 0;
  {
    const Reader t(h5, "summary");
    studyfile::TableReader::ReadOne(t.table(), t.where(), r, [&](auto& a, DiscoveryResult& x) {
      SerializeSummary(a, x, rounds);
    });
  }
  {
    const Reader t(h5, "surfaces");
    for (const SurfaceRow& row : studyfile::TableReader::Read<SurfaceRow>(
             t.table(), t.where(), [](auto&a, SurfaceRow&x) { Serialize(a, x); }))
      (row.model == "baseline" ? r.baseline : r.final_model).push_back(row.fit);
  }
  {
    const Reader t(h5, "effects");
    for (const EffectRow& row : studyfile::TableReader::Read<EffectRow>(
             t.table(), t.where(), [](auto&a, EffectRow&x) { Serialize(a, x); }))
      r.effects.push_back(row.value);
  }
  for (std::int64_t n = 1; n <= rounds; ++n) {
    const std::string prefix = "rounds/" + std::to_string(n) + "/";
    Round round;
    {
      const Reader t(h5, prefix + "summary");
      studyfile::TableReader::ReadOne(t.table(), t.where(), round,
                                      [](auto& a, Round& x) { SerializeSummary(a, x); });
    }
    round.tests = ReadTests(h5, prefix + "tests");
    round.candidates = ReadCandidates(h5, prefix + "candidates");
    ReadValues(h5, prefix + "candidate_values", "candidate", round.candidates);
    round.gap = ReadGap(h5, prefix + "gap");
    r.rounds.push_back(std::move(round));
  }
  {
    const Reader t(h5, "findings");
    r.findings = studyfile::TableReader::Read<Finding>(
        t.table(), t.where(), [](auto& a, Finding& f) { Serialize(a, f); });
  }
  ReadValues(h5, "finding_values", "finding", r.findings);
  r.remaining = ReadTests(h5, "remaining");
  {
    const Reader t(h5, "residuals");
    r.residuals = studyfile::TableReader::Read<TrialResiduals>(
        t.table(), t.where(), [](auto& a, TrialResiduals& x) { Serialize(a, x); });
  }
  return r;
}

std::optional<DiscoveryOptions> ReadDiscoveryOptions(const std::filesystem::path& h5) {
  if (!studyfile::HasGroup(h5, std::string(kDiscoveryGroup) + "/options")) return std::nullopt;
  const Reader t(h5, "options");
  DiscoveryOptions o;
  // Not stored before it was a setting: shown as absent rather than as today's default.
  o.measurement_floor = std::numeric_limits<double>::quiet_NaN();
  studyfile::TableReader::ReadOne(t.table(), t.where(), o,
                                  [](auto& a, DiscoveryOptions& x) { Serialize(a, x); });
  return o;
}

bool HasDiscovery(const std::filesystem::path& h5) {
  try {
    studyfile::ReadTable(h5, std::string(kDiscoveryGroup) + "/summary");
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace hoof::discovery
