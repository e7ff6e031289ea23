// The baseline's prediction z as the study file's /prediction group, and back
// (docs/hdf5-schema.md, "/prediction").
#include <stdexcept>

#include "discovery/discovery_schema.h"
#include "discovery/discovery_tables.h"

namespace hoof::discovery {
namespace {

template <class Archive, class P>
requires std::is_same_v<std::remove_const_t<P>, BaselinePredictions>
void SerializeSummary(Archive& a, P& p) {
  a.Flag("success", p.success, "1 when the baseline and its noise model were fitted");
  a.Text("message", p.message, "why there are no predictions, or empty");
  a.Integer("trials_skipped", p.trials_skipped, "1",
            "trials without a prediction (not measured, or no fitted surface model)");
}

/// A table of /prediction read with errors that name the file and the table.
studyfile::Table ReadPart(const std::filesystem::path& h5, const std::string& name,
                          std::string& where) {
  const std::string path = std::string(kPredictionGroup) + "/" + name;
  where = h5.string() + ": table " + path;
  try {
    return studyfile::ReadTable(h5, path);
  } catch (const std::exception& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
}

}  // namespace

std::vector<studyfile::Table> PredictionTables(const BaselinePredictions& p) {
  std::vector<studyfile::Table> tables;
  tables.push_back(studyfile::TableWriter::OfOne(
      "summary", "Whether the baseline's prediction intervals could be computed", p,
      [](auto& a, const BaselinePredictions& x) { SerializeSummary(a, x); }));
  std::vector<schema::SurfaceRow> surfaces;
  for (const SurfaceFit& f : p.surfaces) surfaces.push_back({"baseline", f});
  tables.push_back(studyfile::TableWriter::Of(
      "surfaces",
      "The baseline model fitted with its noise model (per surface: zeta, mu, their trial-to-trial "
      "s.d. and the systematic measurement s.d.)",
      surfaces, [](auto& a, const schema::SurfaceRow& r) { schema::Serialize(a, r); }));
  tables.push_back(studyfile::TableWriter::Of(
      "trials",
      "Per measured trial: residual after impact under the baseline model, the s.d. of a new "
      "trial's residual under the noise model (prediction interval), and their ratio z",
      p.trials, [](auto& a, const TrialPrediction& t) { schema::Serialize(a, t); }));
  return tables;
}

std::optional<BaselinePredictions> ReadPredictions(const std::filesystem::path& h5) {
  if (!studyfile::HasGroup(h5, std::string(kPredictionGroup) + "/summary")) return std::nullopt;
  BaselinePredictions p;
  std::string where;
  {
    const studyfile::Table t = ReadPart(h5, "summary", where);
    studyfile::TableReader::ReadOne(
        t, where, p, [](auto& a, BaselinePredictions& x) { SerializeSummary(a, x); });
  }
  {
    const studyfile::Table t = ReadPart(h5, "surfaces", where);
    for (const schema::SurfaceRow& row : studyfile::TableReader::Read<schema::SurfaceRow>(
             t, where, [](auto&a, schema::SurfaceRow&x) { schema::Serialize(a, x); }))
      p.surfaces.push_back(row.fit);
  }
  {
    const studyfile::Table t = ReadPart(h5, "trials", where);
    p.trials = studyfile::TableReader::Read<TrialPrediction>(
        t, where, [](auto& a, TrialPrediction& x) { schema::Serialize(a, x); });
  }
  return p;
}

}  // namespace hoof::discovery
