// The fixture `test_studies`: renders the small studies of the command tests (CommandStudies in
// tests/support/test_studies.h), one test per study,
// before the tests that read them run.
#include "support/test_studies.h"
#include "support/render_studies.h"

using hoof::testing::RenderStudyTest;

INSTANTIATE_TEST_SUITE_P(Small, RenderStudyTest,
                         ::testing::ValuesIn(hoof::testing::CommandStudies()),
                         hoof::testing::StudyTestName);
