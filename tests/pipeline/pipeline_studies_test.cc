// The fixture `pipeline_studies`: renders the studies of trial_analysis_test (PipelineStudies in
// tests/support/test_studies.h), one test per study, before it runs.
#include "support/render_studies.h"
#include "support/test_studies.h"

using hoof::testing::RenderStudyTest;

INSTANTIATE_TEST_SUITE_P(Pipeline, RenderStudyTest,
                         ::testing::ValuesIn(hoof::testing::PipelineStudies()),
                         hoof::testing::StudyTestName);
