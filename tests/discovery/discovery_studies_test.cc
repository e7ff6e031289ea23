// The fixture `discovery_studies`: renders every study discovery_test reads
// (tests/discovery/discovery_studies.h), one test per study, before discovery_test runs.
#include "discovery_studies.h"
#include "support/render_studies.h"

using hoof::testing::RenderStudyTest;

INSTANTIATE_TEST_SUITE_P(Discovery, RenderStudyTest,
                         ::testing::ValuesIn(hoof::testing::DiscoveryStudies()),
                         hoof::testing::StudyTestName);
