#include "studyfile/stats_tables.h"

#include <H5Cpp.h>

#include <stdexcept>

#include "studyfile/hdf5_util.h"

namespace hoof::studyfile {
namespace {

/// Reads the tables of /stats from one study file.
class StatsReader {
 public:
  explicit StatsReader(std::filesystem::path h5) : h5_(std::move(h5)) {}

  /// Whether /stats/<name> exists.
  bool Has(const std::string& name) const { return HasGroup(h5_, "/stats/" + name); }

  /// The rows of /stats/<name>, which must exist.
  template <class Row>
  StoredTable<Row> Read(const std::string& name) const {
    const Table t = ReadTable(h5_, "/stats/" + name);
    return {t.description, TableReader::Read<Row>(t, h5_.string() + ":/stats/" + name,
                                                  [](auto& a, auto& row) { Serialize(a, row); })};
  }

  StoredScale Scale(const std::string& prefix) const {
    return {Read<GroupRow>(prefix + "groups"), Read<AnovaRow>(prefix + "anova"),
            Read<VarianceTestRow>(prefix + "tests"), Read<LsdRow>(prefix + "lsd")};
  }

  std::string GroupDescription() const {
    H5::Exception::dontPrint();
    try {
      const H5::H5File file(h5_.string(), H5F_ACC_RDONLY);
      const H5::Group g = file.openGroup("/stats");
      return g.attrExists("description")
                 ? h5::GetAttrText(g, "description", h5_.string() + ":/stats")
                 : "";
    } catch (const H5::Exception& e) {
      throw std::runtime_error(h5_.string() + ":/stats: " + e.getDetailMsg());
    }
  }

 private:
  std::filesystem::path h5_;
};

}  // namespace

bool HasStatistics(const std::filesystem::path& h5) { return HasGroup(h5, "/stats"); }

StoredStatistics ReadStatistics(const std::filesystem::path& h5) {
  if (!HasStatistics(h5)) throw std::runtime_error(h5.string() + " has no /stats");
  const StatsReader in(h5);
  StoredStatistics s;
  s.description = in.GroupDescription();
  s.excluded = in.Read<ExcludedRow>("excluded").rows;
  for (const std::string response : kStatsResponses) {
    if (!in.Has(StatsTableName(response, "cells"))) continue;
    StoredResponse r;
    r.response = response;
    r.cells = in.Read<CellRow>(StatsTableName(response, "cells"));
    for (CellRow& c : r.cells.rows) c.response = response;
    for (const std::string factor : kStatsFactors) {
      const std::string prefix = FactorPrefix(response, factor);
      if (!in.Has(prefix + "anova")) continue;
      StoredFactor f;
      f.factor = factor;
      f.original = in.Scale(prefix);
      const auto transform = in.Read<TransformRow>(prefix + "transform");
      if (transform.rows.size() != 1)
        throw std::runtime_error(h5.string() + ":/stats/" + prefix + "transform has " +
                                 std::to_string(transform.rows.size()) + " rows, not 1");
      f.transform = transform.rows.front();
      const std::string transformed = FactorPrefix(response, factor, true);
      if (in.Has(transformed + "anova")) f.transformed = in.Scale(transformed);
      r.factors.push_back(std::move(f));
    }
    if (in.Has(StatsTableName(response, "two_way")))
      r.two_way = in.Read<TwoWayRow>(StatsTableName(response, "two_way"));
    r.notes = in.Read<NoteRow>(StatsTableName(response, "notes")).rows;
    s.responses.push_back(std::move(r));
  }
  return s;
}

}  // namespace hoof::studyfile
