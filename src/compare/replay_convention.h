#pragma once
/// @file
/// How a trial is replayed, one convention for both replays: the report's (src/report/
/// replay_html.cc writes these values into the page's replay JSON, and src/report/assets/
/// replay.js draws from them) and the overlay video's (src/overlay/overlay.cc, drawn with
/// OpenCV). It fixes
///  - the glyph and colour of the measured and of the simulated markers, and of the residual
///    arrow: from the measured marker to measured + F (simulated - measured), so that a
///    sub-pixel disagreement is drawn F times longer, F stated in both legends;
///  - the magnification F's default and range;
///  - where a trial's folder is looked for when the study folder has moved.
/// Header only: the report and the overlay both include hoof::compare already.

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace hoof::compare::replay {

/// What a glyph looks like.
enum class GlyphShape {
  kRing,   ///< a circle about the point
  kPlus,   ///< a "+" centred on the point
  kArrow,  ///< a line with an arrow head at its end
};

/// The shape's name in the page's JSON ("ring", "plus", "arrow").
inline const char* ShapeName(GlyphShape shape) {
  switch (shape) {
    case GlyphShape::kRing:
      return "ring";
    case GlyphShape::kPlus:
      return "plus";
    case GlyphShape::kArrow:
      return "arrow";
  }
  return "?";
}

/// One kind of mark of the replay.
struct Glyph {
  const char* key;  ///< its key in the page's JSON
  GlyphShape shape;
  unsigned char r, g, b;  ///< colour, sRGB
  /// Size in marker radii: the ring's radius, the plus's half arm (larger than the ring, so
  /// that a plus on a ring shows its arms outside it), the arrow's head length.
  double size;
  const char* symbol;  ///< ASCII stand-in of the glyph for the video's legend ("o", "+", "->")
  const char* label;   ///< legend text after the glyph (each legend adds its own detail)
};

/// The tracked centre of a marker: a green ring.
inline constexpr Glyph kMeasured{"measured", GlyphShape::kRing, 0x00, 0xe6, 0x76, 1.0,
                                 "o",        "measured marker"};
/// The contact model's marker centre (and, in the video, the simulated outline): a magenta plus.
inline constexpr Glyph kSimulated{"simulated", GlyphShape::kPlus, 0xff, 0x2d, 0x95, 1.4,
                                  "+",         "simulated marker"};
/// A body without markers (a ball, an unmarked outline): its centre of mass C, measured and
/// simulated, in the markers' glyphs and colours.
inline constexpr Glyph kMeasuredCentre{"measured", GlyphShape::kRing,        0x00, 0xe6, 0x76, 1.0,
                                       "o",        "measured centre of mass"};
inline constexpr Glyph kSimulatedCentre{
    "simulated", GlyphShape::kPlus, 0xff, 0x2d, 0x95, 1.4, "+", "simulated centre of mass"};
/// The residual, magnified: a sky-blue arrow from the measured marker.
inline constexpr Glyph kResidual{"residual", GlyphShape::kArrow, 0x00, 0xb0, 0xff, 0.8,
                                 "->",       "residual"};

/// "#00e676".
inline std::string HexColour(const Glyph& g) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s = "#";
  for (const unsigned char c : {g.r, g.g, g.b}) {
    s += kHex[c >> 4];
    s += kHex[c & 15];
  }
  return s;
}

/// The residual arrow's magnification F: its default and range (a whole number).
inline constexpr int kDefaultResidualScale = 20;
inline constexpr int kMinResidualScale = 1;
inline constexpr int kMaxResidualScale = 1000;

/// Throws std::invalid_argument "<field> = <F>: must be a whole number in 1..1000" when F is
/// out of range (`field` names the option's field, e.g. "residual_scale").
inline void ValidateResidualScale(int scale, const std::string& field) {
  if (scale < kMinResidualScale || scale > kMaxResidualScale)
    throw std::invalid_argument(field + " = " + std::to_string(scale) + ": must be in " +
                                std::to_string(kMinResidualScale) + ".." +
                                std::to_string(kMaxResidualScale) +
                                " (the residual arrow's magnification)");
}

/// Where a trial's folder was looked for, and where it was found.
struct TrialFolderSearch {
  std::optional<std::filesystem::path> found;  ///< the folder with trial.json, if any
  std::vector<std::filesystem::path> tried;    ///< every folder looked at, in order
};

/// Looks for a trial's folder (the one holding trial.json), in this order:
///  1. `recorded_dir`, the folder the study file recorded;
///  2. when `moved_study_dir` is given (the study folder's new place), the folder at the same
///     place relative to it as `recorded_dir` was relative to `recorded_study_dir` (or, when
///     it was not inside it, the folder of the same name in `moved_study_dir`);
///  3. the folder of that name in `recorded_study_dir` (a study run from another working
///     folder, with relative trial paths).
inline TrialFolderSearch LocateTrialFolder(const std::filesystem::path& recorded_dir,
                                           const std::filesystem::path& recorded_study_dir,
                                           const std::filesystem::path& moved_study_dir = {}) {
  namespace fs = std::filesystem;
  TrialFolderSearch s;
  auto try_dir = [&](const fs::path& dir) {
    if (s.found || dir.empty()) return;
    for (const fs::path& t : s.tried)
      if (t == dir) return;
    s.tried.push_back(dir);
    std::error_code ec;
    if (fs::is_regular_file(dir / "trial.json", ec)) s.found = dir;
  };
  // Without a trailing separator, so that filename() is the folder's name.
  auto plain = [](const fs::path& p) {
    const fs::path n = p.lexically_normal();
    return n.has_filename() ? n : n.parent_path();
  };
  const fs::path dir = plain(recorded_dir), name = dir.filename();
  try_dir(recorded_dir);
  if (!moved_study_dir.empty() && !name.empty()) {
    const fs::path rel =
        recorded_study_dir.empty() ? fs::path() : dir.lexically_relative(plain(recorded_study_dir));
    const bool inside = !rel.empty() && *rel.begin() != ".." && rel != ".";
    try_dir(moved_study_dir / (inside ? rel : name));
  }
  if (!recorded_study_dir.empty() && !name.empty()) try_dir(recorded_study_dir / name);
  return s;
}

/// Why a trial's folder was not found, for a message after the trial's id: "no trial.json in
/// its recorded folder A, nor in B, C" and, when no new place of the study folder was given
/// (`moved_given` false), how to give one.
inline std::string NotFoundMessage(const TrialFolderSearch& s, bool moved_given) {
  std::string m = "no trial.json in its recorded folder ";
  m += s.tried.empty() ? std::string("(none recorded)") : s.tried.front().string();
  for (std::size_t i = 1; i < s.tried.size(); ++i)
    m += (i == 1 ? ", nor in " : ", ") + s.tried[i].string();
  if (!moved_given) m += "; if the study folder has moved, give its new place with --study-dir";
  return m;
}

}  // namespace hoof::compare::replay
