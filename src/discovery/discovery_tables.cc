#include "discovery/discovery_tables.h"

#include <array>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "discovery/discovery_schema.h"
#include "studyfile/table_archive.h"

namespace hoof::discovery {
namespace {

using namespace schema;

// ---- writing ------------------------------------------------------------------------------

Table TestsTable(const std::string& name, const std::string& description,
                 const std::vector<StructureTest>& tests) {
  return studyfile::TableWriter::Of(name, description, tests,
                                    [](auto& a, const StructureTest& t) { Serialize(a, t); });
}

Table CandidatesTable(const std::string& name, const std::vector<CandidateResult>& candidates) {
  return studyfile::TableWriter::Of(
      name,
      "Every candidate effect of the round, fitted jointly with the per-surface parameters, in "
      "rank order (1 = added or strongest evidence); the values of each are in candidate_values",
      candidates, [](auto& a, const CandidateResult& c) { Serialize(a, c); });
}

/// The values of effects, one row per value: `owner` is the row of the candidate or finding
/// (0-based) in the table they belong to.
struct ValuesOf {
  const std::vector<EffectValue>* values;
  std::string unit;  ///< the owner's
};
Table ValuesTable(const std::string& name, const std::string& description, const std::string& owner,
                  const std::string& owner_description, const std::vector<ValuesOf>& owners) {
  std::vector<ValueRow> rows;
  for (std::size_t i = 0; i < owners.size(); ++i)
    for (const auto& v : *owners[i].values)
      rows.push_back({static_cast<std::int64_t>(i), v, owners[i].unit});
  return studyfile::TableWriter::Of(name, description, rows, [&](auto& a, const ValueRow& r) {
    Serialize(a, r, owner, owner_description);
  });
}

/// The columns of a held-out trial, declared once for writing and reading.
Table GapTable(const std::string& name, const std::vector<GapTrial>& gap) {
  return studyfile::TableWriter::Of(
      name,
      "Per held-out trial: residuals after impact (fractions of the impact speed) of the "
      "current model (before) and with the round's effect (after), each fitted without the "
      "trial's fold",
      gap, [](auto& a, const GapTrial& g) { Serialize(a, g); });
}

/// A row of the surfaces table: which model, and its fit on one surface.
Table SurfacesTable(const DiscoveryResult& r) {
  std::vector<SurfaceRow> rows;
  for (const SurfaceFit& f : r.baseline) rows.push_back({"baseline", f});
  for (const SurfaceFit& f : r.final_model) rows.push_back({"final", f});
  return studyfile::TableWriter::Of(
      "surfaces",
      "The model per surface fitted to every used trial: the baseline (the paper's model) and "
      "the final model (with the accepted effects); k is not identified and stays the paper's. "
      "zeta_sd and mu_sd are the noise model's trial-to-trial scatter of the coefficients, "
      "measurement_sd_* its systematic measurement error on the surface",
      rows, [](auto& a, const SurfaceRow& row) { Serialize(a, row); });
}

/// The one-row summary of the workflow; `rounds` is the number of rounds (tables rounds/<n>).
std::pair<std::string, std::string> ParameterOf(const DiscoveryResult& r, const std::string& key) {
  for (const auto& f : r.findings)
    if (f.key == key) return {f.parameter, f.unit};
  for (const auto& round : r.rounds)
    for (const auto& c : round.candidates)
      if (c.key == key) return {c.parameter, c.unit};
  return {"", ""};
}

}  // namespace

std::vector<Table> DiscoveryTables(const DiscoveryResult& r) {
  std::vector<Table> tables;
  std::int64_t rounds = static_cast<std::int64_t>(r.rounds.size());
  tables.push_back(studyfile::TableWriter::OfOne(
      "summary", "The discovery workflow's outcome (hoofimpact discover; docs/discovery.md)", r,
      [&](auto& a, const DiscoveryResult& x) { SerializeSummary(a, x, rounds); }));
  tables.push_back(SurfacesTable(r));
  {
    std::vector<EffectRow> effects;
    for (const auto& e : r.effects) {
      const auto [parameter, unit] = ParameterOf(r, e.key);
      effects.push_back({e, parameter, unit});
    }
    tables.push_back(studyfile::TableWriter::Of(
        "effects",
        "The final model's effects beyond the paper's model, with their values: one row per "
        "value (a per-surface effect has one per surface)",
        effects, [](auto& a, const EffectRow& e) { Serialize(a, e); }));
  }
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const Round& round = r.rounds[i];
    const std::string prefix = "rounds/" + std::to_string(i + 1) + "/";
    tables.push_back(studyfile::TableWriter::OfOne(
        prefix + "summary",
        "What round " + std::to_string(i + 1) + " decided, and the held-out gap", round,
        [](auto& a, const Round& x) { SerializeSummary(a, x); }));
    tables.push_back(TestsTable(prefix + "tests",
                                "Tests of the current model's residuals for structure (Holm over "
                                "the round's tests)",
                                round.tests));
    tables.push_back(CandidatesTable(prefix + "candidates", round.candidates));
    std::vector<ValuesOf> values;
    for (const auto& c : round.candidates) values.push_back({&c.values, c.unit});
    tables.push_back(ValuesTable(prefix + "candidate_values",
                                 "Every value of each candidate's chosen form (one row for a "
                                 "shared effect, one per surface for a per-surface effect)",
                                 "candidate", "row of the candidate in candidates (0-based)",
                                 values));
    tables.push_back(GapTable(prefix + "gap", round.gap));
  }
  {
    std::vector<ValuesOf> values;
    for (const auto& f : r.findings) values.push_back({&f.values, f.unit});
    tables.push_back(studyfile::TableWriter::Of(
        "findings",
        "What the verdict says about each effect: named, tentative or indistinguishable",
        r.findings, [](auto& a, const Finding& f) { Serialize(a, f); }));
    tables.push_back(ValuesTable("finding_values", "Every value of each finding's effect",
                                 "finding", "row of the finding in findings (0-based)", values));
  }
  tables.push_back(TestsTable("remaining",
                              "The significant disagreements the final model leaves (no rows: "
                              "none)",
                              r.remaining));
  tables.push_back(studyfile::TableWriter::Of(
      "residuals",
      "Per used trial: residuals after impact (measured - simulated, fractions of the impact "
      "speed) under the baseline and the final model, fitted to every trial",
      r.residuals, [](auto& a, const TrialResiduals& t) { Serialize(a, t); }));
  return tables;
}

Table DiscoveryOptionsTable(const DiscoveryOptions& o) {
  return studyfile::TableWriter::OfOne("options", "The settings the discovery workflow ran with", o,
                                       [](auto& a, const auto& x) { Serialize(a, x); });
}

}  // namespace hoof::discovery
