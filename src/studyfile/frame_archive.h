#pragma once
/// @file
/// Archives of per-frame arrays (internal to hoof::study_file): a trial's marker tracks, one
/// MarkerObservation per [frame, marker], and its poses, one BodyPose per [frame]. The fields of
/// one element are declared once, in a Serialize() of studyfile/schema.h, as for a group (the
/// pattern of studyfile/archive.h); ElementWriter gathers each field over all the elements into
/// one dataset, ElementReader reads the datasets back into the elements, every shape checked.
/// FramesWriter and FramesReader archive the group that holds such arrays: an H5Writer or
/// H5Reader, plus the frame times, the elements and a per-frame number of the trial, so that
/// the whole group (`/trials/<id>/tracks`, `.../poses`) is one declaration.
///
/// A field measured only for some elements (the centre of a marker that was found, the numbers
/// of a valid pose) is declared with the flag that says so (`NumberIf(o.found, ...)`): NaN in
/// the file when the flag is not set, and left at its default when read.
#include <H5Cpp.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "core/frames.h"
#include "studyfile/archive.h"
#include "studyfile/hdf5_util.h"

namespace hoof::studyfile::internal {

/// Writes the fields of an array of elements (row-major over its shape `dims`, such as
/// [frame, marker]): one dataset per field, of shape `dims`, plus [2] for a point.
class ElementWriter {
 public:
  static constexpr bool kWriting = true;

  /// Writes `elements`, each visited by Serialize(archive, element), into `group`. A default
  /// element declares the datasets first, so that an array of no elements still has them.
  template <class Element>
  static void Write(const H5::Group& group, const std::vector<hsize_t>& dims,
                    const std::vector<Element>& elements) {
    ElementWriter w;
    const Element declared{};
    Serialize(w, declared);
    w.declaring_ = false;
    for (const Element& e : elements) Serialize(w, e);
    w.WriteDatasets(group, dims);
  }

  void Number(const std::string& name, double v, const std::string& units,
              const std::string& description) {
    Put(name, units, description, {v});
  }
  /// A number measured only when `present`: NaN in the file otherwise.
  void NumberIf(bool present, const std::string& name, double v, const std::string& units,
                const std::string& description) {
    Number(name, present ? v : core::kNaN, units, description);
  }
  /// A number measured only when `present`, whose "not measured" is 0 in memory (as
  /// H5Writer::NumberZeroUnmeasured; a distance, never negative): NaN in the file unless
  /// `present` and `v` > 0.
  void NumberZeroUnmeasuredIf(bool present, const std::string& name, double v,
                              const std::string& units, const std::string& description) {
    Number(name, present && v > 0 ? v : core::kNaN, units, description);
  }
  /// A point (x, y) measured only when `present`: two numbers per element, NaN otherwise.
  void Vec2If(bool present, const std::string& name, const Eigen::Vector2d& v,
              const std::string& units, const std::string& description) {
    if (present)
      Put(name, units, description, {v.x(), v.y()});
    else
      Put(name, units, description, {core::kNaN, core::kNaN});
  }
  /// A boolean, as uint8 0/1 (units "").
  void Flag(const std::string& name, bool v, const std::string& description) {
    Put<std::uint8_t>(name, "", description, {v ? std::uint8_t{1} : std::uint8_t{0}});
  }
  /// An integer, 32 bits in the file.
  void Int32(const std::string& name, int v, const std::string& units,
             const std::string& description) {
    Put<std::int32_t>(name, units, description, {static_cast<std::int32_t>(v)});
  }
  /// Text (units "").
  void Text(const std::string& name, const std::string& v, const std::string& description) {
    Put<std::string>(name, "", description, {v});
  }

 private:
  /// One field over all the elements: `width` values per element, in element order.
  struct Dataset {
    std::string name, units, description;
    std::size_t width = 1;
    std::variant<std::vector<double>, std::vector<std::uint8_t>, std::vector<std::int32_t>,
                 std::vector<std::string>>
        values;
  };

  ElementWriter() = default;

  /// Declares the dataset `name` (while declaring), else appends one element's `values` to it.
  template <class T>
  void Put(const std::string& name, const std::string& units, const std::string& description,
           std::initializer_list<T> values) {
    if (declaring_) {
      datasets_.push_back({name, units, description, values.size(), std::vector<T>{}});
      return;
    }
    std::vector<T>& all = std::get<std::vector<T>>(Find(name).values);
    all.insert(all.end(), values);
  }
  /// The declared dataset `name`; an element that visits another is a bug of its Serialize.
  Dataset& Find(const std::string& name);
  void WriteDatasets(const H5::Group& group, const std::vector<hsize_t>& dims) const;

  std::vector<Dataset> datasets_;  ///< in the order declared: the order they are written in
  bool declaring_ = true;
};

/// Reads the fields of an array of elements back from the datasets ElementWriter wrote; an
/// error names the file, the group and the dataset.
class ElementReader {
 public:
  static constexpr bool kWriting = false;

  /// Fills `elements` (row-major over `dims`) from `group`, each visited by
  /// Serialize(archive, element). A visit of a default element first reads every dataset, its
  /// shape checked, so that an array of no elements is checked too.
  template <class Element>
  static void Read(const GroupReader& group, const std::vector<hsize_t>& dims,
                   std::vector<Element>& elements) {
    ElementReader r(group, dims);
    Element declared{};
    Serialize(r, declared);
    r.loading_ = false;
    for (r.i_ = 0; r.i_ < elements.size(); ++r.i_) {
      Serialize(r, elements[r.i_]);
      r.AssignPending();
    }
  }

  void Number(const std::string& name, double& v, const std::string& /*units*/,
              const std::string& /*description*/) {
    if (const std::vector<double>* x = Doubles(name, 1)) v = (*x)[i_];
  }
  void NumberIf(const bool& present, const std::string& name, double& v,
                const std::string& /*units*/, const std::string& /*description*/) {
    if (const std::vector<double>* x = Doubles(name, 1))
      pending_.push_back({&present, &v, (*x)[i_]});
  }
  /// NaN reads back as 0.
  void NumberZeroUnmeasuredIf(const bool& present, const std::string& name, double& v,
                              const std::string& /*units*/, const std::string& /*description*/) {
    if (const std::vector<double>* x = Doubles(name, 1))
      pending_.push_back({&present, &v, std::isnan((*x)[i_]) ? 0.0 : (*x)[i_]});
  }
  void Vec2If(const bool& present, const std::string& name, Eigen::Vector2d& v,
              const std::string& /*units*/, const std::string& /*description*/) {
    if (const std::vector<double>* x = Doubles(name, 2)) {
      pending_.push_back({&present, &v.x(), (*x)[2 * i_]});
      pending_.push_back({&present, &v.y(), (*x)[2 * i_ + 1]});
    }
  }
  void Flag(const std::string& name, bool& v, const std::string& /*description*/) {
    if (const std::vector<std::int64_t>* x = Integers(name)) v = (*x)[i_] != 0;
  }
  /// An integer that must fit an int.
  void Int32(const std::string& name, int& v, const std::string& /*units*/,
             const std::string& /*description*/);
  void Text(const std::string& name, std::string& v, const std::string& /*description*/) {
    if (const std::vector<std::string>* x = Texts(name)) v = (*x)[i_];
  }

 private:
  /// A value of a field read `...If` a flag of the element: assigned when the element's visit
  /// is over, so that the flag may be declared after the field (p_I_px comes before found).
  struct Pending {
    const bool* present;
    double* field;
    double value;
  };

  ElementReader(GroupReader group, std::vector<hsize_t> dims)
      : group_(std::move(group)), dims_(std::move(dims)) {}

  /// While loading: reads the dataset `name` of `width` numbers per element, its shape
  /// checked, and gives nullptr. After: the numbers read.
  const std::vector<double>* Doubles(const std::string& name, hsize_t width);
  /// The same for a dataset of integers, one per element.
  const std::vector<std::int64_t>* Integers(const std::string& name);
  /// The same for a dataset of text, one per element.
  const std::vector<std::string>* Texts(const std::string& name);
  /// Assigns the values read `...If` a flag that is set, and forgets them.
  void AssignPending();

  GroupReader group_;
  std::vector<hsize_t> dims_;
  std::map<std::string, std::vector<double>> doubles_;
  std::map<std::string, std::vector<std::int64_t>> integers_;
  std::map<std::string, std::vector<std::string>> texts_;
  std::vector<Pending> pending_;
  std::size_t i_ = 0;  ///< the element visited
  bool loading_ = true;
};

/// Writes a group that holds per-frame arrays: an H5Writer (for its lists and scalars) that
/// also writes the frame times, the fields of per-frame elements and a per-frame number.
class FramesWriter : public H5Writer {
 public:
  using H5Writer::H5Writer;

  /// The time of each frame of `frames` since frame 0, f / fps (NaN without a frame rate),
  /// shape [frame]. The reader takes the number of frames from it.
  template <class Frame>
  void FrameTimes(const std::string& name, const std::vector<Frame>& frames, double fps,
                  const std::string& units, const std::string& description) {
    std::vector<double> t(frames.size(), core::kNaN);
    if (fps > 0)
      for (std::size_t f = 0; f < t.size(); ++f) t[f] = static_cast<double>(f) / fps;
    h5::Doubles(group(), name, t, {t.size()}, units, description);
  }
  /// The fields of one element per frame (its Serialize), each a dataset of shape [frame].
  template <class Element>
  void PerFrame(const std::vector<Element>& frames) {
    ElementWriter::Write(group(), {frames.size()}, frames);
  }
  /// The fields of one element per frame and marker, each a dataset of shape [frame, marker]. A
  /// frame of fewer than `markers` elements is padded with default ones (a marker not found).
  template <class Element>
  void PerFrameAndMarker(const std::vector<std::vector<Element>>& frames, std::size_t markers) {
    std::vector<Element> flat(frames.size() * markers);
    for (std::size_t f = 0; f < frames.size(); ++f)
      std::copy_n(frames[f].begin(), std::min(markers, frames[f].size()),
                  flat.begin() + static_cast<std::ptrdiff_t>(f * markers));
    ElementWriter::Write(group(), {frames.size(), markers}, flat);
  }
  /// One number for each of `frames` frames, shape [frame]: NaN beyond the end of `v`.
  void FrameNumbers(const std::string& name, const std::vector<double>& v, std::size_t frames,
                    const std::string& units, const std::string& description) {
    std::vector<double> x(frames, core::kNaN);
    std::copy_n(v.begin(), std::min(frames, v.size()), x.begin());
    h5::Doubles(group(), name, x, {frames}, units, description);
  }
};

/// Reads a group that FramesWriter wrote.
class FramesReader : public H5Reader {
 public:
  using H5Reader::H5Reader;

  /// Makes `frames` as many default frames as the frame times say (the times are not kept).
  template <class Frame>
  void FrameTimes(const std::string& name, std::vector<Frame>& frames, double /*fps*/,
                  const std::string& /*units*/, const std::string& /*description*/) const {
    frames.assign(group().Length(name), Frame{});
  }
  template <class Element>
  void PerFrame(std::vector<Element>& frames) const {
    ElementReader::Read(group(), {frames.size()}, frames);
  }
  /// Makes each of `frames` `markers` elements, read from the [frame, marker] datasets.
  template <class Element>
  void PerFrameAndMarker(std::vector<std::vector<Element>>& frames, std::size_t markers) const {
    std::vector<Element> flat(frames.size() * markers);
    ElementReader::Read(group(), {frames.size(), markers}, flat);
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const auto first = flat.begin() + static_cast<std::ptrdiff_t>(f * markers);
      frames[f].assign(first, first + static_cast<std::ptrdiff_t>(markers));
    }
  }
  void FrameNumbers(const std::string& name, std::vector<double>& v, std::size_t frames,
                    const std::string& /*units*/, const std::string& /*description*/) const {
    v = group().Doubles(name, {frames});
  }
};

}  // namespace hoof::studyfile::internal
