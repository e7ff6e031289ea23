#pragma once
/// @file
/// The studies the tests outside tests/discovery read, by name, in two catalogs: those of
/// trial_analysis_test (PipelineStudies, the fixture `pipeline_studies`, label slow) and the small
/// ones of the command tests (CommandStudies, the fixture `test_studies`), each rendered by its
/// fixture before the tests that read them run (tests/support/render_studies.h).
/// A test reads one with TestStudyDir(name): rendered once per renderer, shared by every test
/// process that reads it (a test copies a study before it breaks it). discovery_test's studies
/// have their own catalog and fixture (tests/discovery/discovery_studies.h).

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/rendered_study.h"

namespace hoof::testing {

/// The studies of tests/pipeline/trial_analysis_test.cc.
inline const std::vector<TestStudy>& PipelineStudies() {
  static const std::vector<TestStudy> studies = {
      // The paper-sized study (3 surfaces x 4 angles x 4 speeds x 3 repetitions) at the
      // renderer's default realism (tests/pipeline/trial_analysis_test.cc).
      {"full_study", "--seed 2026", ""},
      // Four trials with a tilt and a tilt rate the out-of-plane check must flag.
      {"out_of_plane",
       "--seed 7 --surfaces concrete,asphalt --angles-deg 10,20 --speeds 3 --trials-per-cell 1 "
       "--tilt-deg 6 --tilt-rate-deg-s 3000",
       ""},
      // Four trials with a tilt growing at 1000 deg/s, re-measured with their motion.
      {"out_of_plane_rate",
       "--seed 11 --surfaces steel,asphalt --angles-deg 0,30 --speeds 3 --trials-per-cell 1 "
       "--tilt-rate-deg-s 1000",
       ""},
      // One oblique trial, copied and broken by the bad-input tests.
      {"bad_input_base", "--seed 3 --surfaces steel --angles-deg 20 --speeds 3 --trials-per-cell 1",
       ""},
  };
  return studies;
}

/// The small studies of the command tests (analyze, figures, report, overlay, run) and of
/// tests/compare/trial_comparison_test.cc.
inline const std::vector<TestStudy>& CommandStudies() {
  static const std::vector<TestStudy> studies = {
      // 2 surfaces x 2 angles x 1 speed x 2 repetitions = 8 short trials
      // (tests/studyfile/analyze_command_test.cc).
      {"analyze_8",
       "--surfaces steel,concrete --angles-deg 0,20 --speeds 3 --trials-per-cell 2 "
       "--frames-before 26 --frames-after 26 --seed 11",
       ""},
      // 2 surfaces x 2 angles x 2 speeds x 2 repetitions = 16 short trials
      // (tests/report/figures_command_test.cc).
      {"figures_16",
       "--surfaces steel,asphalt --angles-deg 0,20 --speeds 2,3 --trials-per-cell 2 "
       "--frames-before 26 --frames-after 26 --seed 5",
       ""},
      // 2 surfaces x 2 angles, one trial each, no scatter (tests/report/html_report_test.cc).
      {"report_4",
       "--no-scatter --surfaces steel,asphalt --angles-deg 0,20 --speeds 3 --trials-per-cell 1 "
       "--seed 3",
       ""},
      // One surface, two angles, no scatter (tests/overlay/overlay_command_test.cc).
      {"overlay_2",
       "--no-scatter --surfaces steel --angles-deg 0,20 --speeds 3 --trials-per-cell 1", ""},
      // 2 surfaces x 2 angles x 3 speeds without scatter: the fitted surface model is the truth
      // (tests/compare/trial_comparison_test.cc).
      {"compare_12",
       "--no-scatter --surfaces steel,asphalt --angles-deg 0,20 --speeds 2,3,4 "
       "--trials-per-cell 1 --seed 4",
       ""},
      // 3 surfaces x 1 angle x 4 repetitions = 12 short normal trials whose e varies more on
      // asphalt than on steel (the paper's spreads), by enough with this seed for Bartlett to
      // reject equal variances of e by surface (p = 0.0016 as measured), so that e by surface is
      // analysed on a Box-Cox scale (lambda = 3); the report must say so
      // (tests/report/stats_report_test.cc).
      {"stats_transformed",
       "--surfaces steel,concrete,asphalt --angles-deg 0 --speeds 3 --trials-per-cell 4 "
       "--frames-before 26 --frames-after 26 --seed 26",
       ""},
      // 2 surfaces x 2 angles x 2 speeds x 2 repetitions without scatter
      // (tests/cli/run_command_test.cc).
      {"run_16",
       "--no-scatter --surfaces steel,concrete --angles-deg 0,20 --speeds 2.5,3.5 "
       "--trials-per-cell 2 --seed 8",
       ""},
      // The whole job on bodies without markers: a ball (study.json's ball specimen, a solid
      // sphere) and the unmarked specimen, each 2 surfaces x 2 angles x 2 speeds of short trials
      // without scatter, so the fitted contact law is the truth's; 8 trials, discovery's least
      // (tests/compare/trial_comparison_test.cc, tests/pipeline/truth_score_test.cc and the
      // command tests of run, score, overlay, report and discover).
      {"ball_8",
       "--body ball --no-scatter --surfaces steel,asphalt --angles-deg 0,20 --speeds 2.5,3.5 "
       "--trials-per-cell 1 --frames-before 26 --frames-after 26 --seed 21",
       ""},
      {"unmarked_8",
       "--body unmarked --no-scatter --surfaces steel,asphalt --angles-deg 0,20 --speeds 2.5,3.5 "
       "--trials-per-cell 1 --frames-before 26 --frames-after 26 --seed 22",
       ""},
  };
  return studies;
}

/// The folder of the study `name` of either catalog, which its fixture rendered (or, where
/// the test runs without it, renders now). A name missing from the catalog fails the test.
inline std::filesystem::path TestStudyDir(const std::string& name) {
  for (const auto* catalog : {&PipelineStudies(), &CommandStudies()})
    for (const TestStudy& s : *catalog)
      if (s.name == name) return RenderedStudy(s);
  ADD_FAILURE() << "no study " << name << " in tests/support/test_studies.h";
  return {};
}

}  // namespace hoof::testing
