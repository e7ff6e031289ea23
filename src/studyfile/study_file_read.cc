// Reading a study file back: ReadStudyResults, ReadTrialAnalyses, ReadKinematicsOptions
// (studyfile/study_file.h).
#include "studyfile/study_file.h"

#include <H5Cpp.h>

#include <stdexcept>

#include "studyfile/file_util.h"
#include "studyfile/frame_archive.h"
#include "studyfile/hdf5_util.h"
#include "studyfile/schema.h"
#include "studyfile/table_archive.h"

namespace hoof::studyfile {
namespace {

using internal::CheckedStrings;
using internal::CheckFormat;
using internal::GroupReader;
using internal::RethrowHdf5;

// ------------------------------------------------------------------------------------------
// Reading trials back
// ------------------------------------------------------------------------------------------

/// One `/trials/<id>` group; the specimen is filled in by the caller.
pipeline::TrialAnalysis ReadTrialGroup(const GroupReader& g) {
  pipeline::TrialAnalysis r;
  internal::SerializeOutcome(internal::H5Reader(g), r);
  internal::SerializeMetadata(internal::H5Reader(g.Group("metadata")), r);
  internal::SerializeTracks(internal::FramesReader(g.Group("tracks")), r);
  internal::SerializePoses(internal::FramesReader(g.Group("poses")), r);
  r.impact.message = g.Text("impact_message");
  if (g.Has("results")) {  // written only when the impact was measured, with the fits
    r.impact.success = true;
    const GroupReader fits = g.Group("fits");
    internal::Serialize(internal::H5Reader(fits.Group("before")), r.impact.before);
    internal::Serialize(internal::H5Reader(fits.Group("after")), r.impact.after);
    internal::Serialize(internal::H5Reader(g.Group("results")), r.impact);
  }
  return r;
}

}  // namespace

// ------------------------------------------------------------------------------------------
// Reading
// ------------------------------------------------------------------------------------------

StudyResults ReadStudyResults(const std::filesystem::path& path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  StudyResults out;
  std::vector<std::string> group;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    const H5::Group root = file.openGroup("/");
    CheckFormat(root, path);
    out.name = h5::GetAttrText(root, "name", path.string());
    out.study_dir = h5::GetAttrText(root, "study_dir", path.string());
    out.hoofimpact_version = h5::GetAttrText(root, "hoofimpact_version", path.string());
    out.created_utc = h5::GetAttrText(root, "created_utc", path.string());
    if (root.attrExists("command_line"))
      out.command_line = h5::GetAttrText(root, "command_line", path.string());
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  out.trials = TableReader::Read<TrialResult>(
      ReadTable(path, "/results"), path.string() + ": table /results",
      [](auto& a, TrialResult& r) { internal::SerializeResult(a, r); });
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    for (TrialResult& r : out.trials) {
      const std::string where = path.string() + ":" + r.group;
      if (!h5::PathExists(file.openGroup("/"), r.group))
        throw std::runtime_error(where + " does not exist");
      const H5::Group g = file.openGroup(r.group);
      r.flags = h5::ReadTexts(g.openDataSet("flags"), where + "/flags");
      r.warnings = h5::ReadTexts(g.openDataSet("warnings"), where + "/warnings");
    }
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  return out;
}

kinematics::KinematicsOptions ReadKinematicsOptions(const std::filesystem::path& path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  kinematics::KinematicsOptions k;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    const H5::Group root_group = file.openGroup("/");
    CheckFormat(root_group, path);
    const GroupReader g =
        GroupReader(root_group, path.string() + ":").Group("study").Group("analysis_options");
    internal::Serialize(internal::H5Reader(g), k);
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  try {
    k.Validate();
  } catch (const std::exception& e) {
    throw std::runtime_error(path.string() + ":/study/analysis_options: " + e.what());
  }
  return k;
}

std::vector<pipeline::TrialAnalysis> ReadTrialAnalyses(const std::filesystem::path& path) {
  H5::Exception::dontPrint();
  if (!std::filesystem::is_regular_file(path))
    throw std::runtime_error(path.string() + ": no such file");
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    CheckFormat(file.openGroup("/"), path);
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  const Table results = ReadTable(path, "/results");
  std::vector<std::string> ids, groups;
  try {
    ids = CheckedStrings(results, "id");
    groups = CheckedStrings(results, "group");
  } catch (const std::exception& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
  std::vector<pipeline::TrialAnalysis> out;
  try {
    const H5::H5File file(path.string(), H5F_ACC_RDONLY);
    const H5::Group root_group = file.openGroup("/");
    const GroupReader root(root_group, path.string() + ":");
    std::map<std::string, pipeline::SpecimenSpec> specimens;  // read once each
    for (std::size_t i = 0; i < groups.size(); ++i) {
      const std::string where = path.string() + ":" + groups[i];
      if (groups[i].size() < 2 || groups[i].front() != '/')
        throw std::runtime_error(path.string() + ":/results/group row " + std::to_string(i) +
                                 " is \"" + groups[i] + "\", not a group path");
      if (!h5::PathExists(root_group, groups[i]))
        throw std::runtime_error(where + " does not exist");
      if (root_group.childObjType(groups[i]) != H5O_TYPE_GROUP)
        throw std::runtime_error(where + " is not a group");
      pipeline::TrialAnalysis r = ReadTrialGroup(GroupReader(file.openGroup(groups[i]), where));
      if (r.spec.id != ids[i])
        throw std::runtime_error(where + "/metadata/id is \"" + r.spec.id +
                                 "\", /results/id says \"" + ids[i] + "\"");
      const GroupReader trial(file.openGroup(groups[i]), where);
      if (trial.Has("specimen")) {
        // The trial's own specimen (files from before it was written have only the study's).
        internal::Serialize(internal::H5Reader(trial.Group("specimen")), r.spec.specimen);
      } else if (!r.spec.specimen_id.empty()) {
        auto it = specimens.find(r.spec.specimen_id);
        if (it == specimens.end()) {
          const GroupReader g = root.Group("study").Group("specimens").Group(r.spec.specimen_id);
          pipeline::SpecimenSpec specimen;
          internal::Serialize(internal::H5Reader(g), specimen);
          it = specimens.emplace(r.spec.specimen_id, std::move(specimen)).first;
        }
        r.spec.specimen = it->second;
      }
      out.push_back(std::move(r));
    }
  } catch (const H5::Exception& e) {
    RethrowHdf5(e, path);
  }
  return out;
}

}  // namespace hoof::studyfile
