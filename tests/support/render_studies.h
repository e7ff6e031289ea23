#pragma once
/// @file
/// The test that renders a catalog of studies: the setup of a CTest fixture.
///
/// A catalog (tests/support/test_studies.h, tests/discovery/discovery_studies.h) is instantiated
/// in an executable of its own,
///     INSTANTIATE_TEST_SUITE_P(Discovery, RenderStudyTest, ::testing::ValuesIn(Catalog()),
///                              hoof::testing::StudyTestName);
/// registered with `FIXTURES_SETUP <catalog>`; the test executables that read its studies require
/// that fixture (`FIXTURES_REQUIRED`, tests/HoofTest.cmake). ctest then renders each study once,
/// one test per study (in parallel under -j), before any test that reads it starts, and a test
/// picked alone with -R still gets its studies rendered first. A study already rendered by this
/// renderer is not rendered again (RenderedStudy).

#include <cctype>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "support/rendered_study.h"

namespace hoof::testing {

class RenderStudyTest : public ::testing::TestWithParam<TestStudy> {};

TEST_P(RenderStudyTest, IsRendered) {
  const std::filesystem::path dir = RenderedStudy(GetParam());
  EXPECT_TRUE(std::filesystem::exists(dir / "study.json")) << dir;
}

/// A study's test name: its name, with what gtest refuses in a name replaced by '_'.
inline std::string StudyTestName(const ::testing::TestParamInfo<TestStudy>& info) {
  std::string name = info.param.name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

}  // namespace hoof::testing
