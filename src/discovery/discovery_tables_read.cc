// Reading the study file's /discovery group back (discovery/discovery_tables.h).
#include <cstdint>
#include <exception>
#include <filesystem>
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

/// One table of the file, with column access that names the file, the table and the column.
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
    rows_ = table_.columns.empty() ? 0 : table_.columns.front().size();
  }

  std::size_t rows() const { return rows_; }
  const Table& table() const { return table_; }
  /// "<file>: table <path>", how errors name the table.
  std::string where() const { return h5_.string() + ": table " + path_; }

  std::vector<double> Numbers(const std::string& name) const {
    const auto& c = Find(name);
    if (const auto* d = std::get_if<std::vector<double>>(&c.values)) return *d;
    if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values))
      return std::vector<double>(i->begin(), i->end());
    throw Error(name, "is not numeric");
  }
  std::vector<std::int64_t> Integers(const std::string& name) const {
    const auto& c = Find(name);
    if (const auto* i = std::get_if<std::vector<std::int64_t>>(&c.values)) return *i;
    if (const auto* d = std::get_if<std::vector<double>>(&c.values)) {
      std::vector<std::int64_t> out;
      for (double x : *d) out.push_back(static_cast<std::int64_t>(x));
      return out;
    }
    throw Error(name, "is not numeric");
  }
  bool Has(const std::string& name) const {
    for (const auto& c : table_.columns)
      if (c.name == name) return true;
    return false;
  }
  std::vector<bool> Flags(const std::string& name) const {
    std::vector<bool> out;
    for (auto i : Integers(name)) out.push_back(i != 0);
    return out;
  }
  std::vector<std::string> Texts(const std::string& name) const {
    const auto& c = Find(name);
    if (const auto* s = std::get_if<std::vector<std::string>>(&c.values)) return *s;
    throw Error(name, "is not text");
  }
  /// A text column of enum values, each read with `parse` (a FromString function).
  template <typename Enum>
  std::vector<Enum> Enums(const std::string& name, Enum (*parse)(const std::string&)) const {
    std::vector<Enum> out;
    const auto texts = Texts(name);
    for (std::size_t i = 0; i < texts.size(); ++i) {
      try {
        out.push_back(parse(texts[i]));
      } catch (const std::exception& e) {
        throw Error(name, "row " + std::to_string(i) + ": " + e.what());
      }
    }
    return out;
  }
  /// The error for a bad value of column `column`.
  std::runtime_error Error(const std::string& column, const std::string& what) const {
    return std::runtime_error(h5_.string() + ": table " + path_ + ": column \"" + column + "\" " +
                              what);
  }

 private:
  const Column& Find(const std::string& name) const {
    for (const auto& c : table_.columns)
      if (c.name == name) return c;
    throw Error(name, "is missing");
  }

  std::filesystem::path h5_;
  std::string path_;
  Table table_;
  std::size_t rows_ = 0;
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
  const auto row = t.Integers(owner);
  const auto key = t.Texts("key"), surface = t.Texts("surface");
  const auto value = t.Numbers("value"), se = t.Numbers("se");
  for (std::size_t i = 0; i < t.rows(); ++i) {
    if (row[i] < 0 || static_cast<std::size_t>(row[i]) >= owners.size())
      throw t.Error(owner, "row " + std::to_string(i) + ": " + std::to_string(row[i]) +
                               " is not a row of the " + std::to_string(owners.size()) +
                               " it refers to");
    owners[static_cast<std::size_t>(row[i])].values.push_back(
        EffectValue{key[i], surface[i], value[i], se[i]});
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

bool HasDiscovery(const std::filesystem::path& h5) {
  try {
    studyfile::ReadTable(h5, std::string(kDiscoveryGroup) + "/summary");
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace hoof::discovery
