# hoof_add_test(NAME <name> SOURCES <files...> LIBS <targets...> [LABELS <label>]
#               [TIMEOUT <s>] [FIXTURES_SETUP <fixture>] [FIXTURES_REQUIRED <fixture>])
# FIXTURES_SETUP makes every test of the executable a setup of <fixture> (the renderers of the
# test studies, tests/support/render_studies.h); FIXTURES_REQUIRED makes ctest run those first.
# One label per executable: gtest_discover_tests writes a list of labels unquoted, and ctest
# would read the second as a property name.
# Builds one gtest executable and registers its tests with CTest (gtest_discover_tests),
# running from the project root so tests can find tests/data and sample_frames.
include(GoogleTest)
function(hoof_add_test)
  cmake_parse_arguments(ARG "" "NAME;TIMEOUT;FIXTURES_SETUP;FIXTURES_REQUIRED"
    "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main hoof_warnings)
  target_include_directories(${ARG_NAME} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_compile_features(${ARG_NAME} PRIVATE cxx_std_20)
  target_compile_definitions(${ARG_NAME} PRIVATE
    HOOF_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    HOOF_BINARY_DIR="${PROJECT_BINARY_DIR}"
    HOOF_CLI_PATH="$<TARGET_FILE:hoofimpact>"
    # What `hoofimpact synth` is built from: the renderer's libraries (deterministic archives)
    # and the command's sources, with the OpenCV that encodes its PNG frames (RenderedStudy).
    HOOF_RENDERER_FILES="$<TARGET_FILE:hoof_synth>|$<TARGET_FILE:hoof_dynamics>|$<TARGET_FILE:hoof_core>|$<TARGET_FILE:hoof_io>|${PROJECT_SOURCE_DIR}/src/cli/synth_command.cc|${PROJECT_SOURCE_DIR}/src/cli/common_options.cc|${PROJECT_SOURCE_DIR}/src/cli/common_options.h|${PROJECT_SOURCE_DIR}/src/cli/main.cc"
    HOOF_RENDERER_OPENCV="${OpenCV_VERSION}")
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  set(fixtures)
  if(ARG_FIXTURES_SETUP)
    list(APPEND fixtures FIXTURES_SETUP ${ARG_FIXTURES_SETUP})
    add_dependencies(${ARG_NAME} hoofimpact)  # it renders with the program
  endif()
  if(ARG_FIXTURES_REQUIRED)
    list(APPEND fixtures FIXTURES_REQUIRED ${ARG_FIXTURES_REQUIRED})
  endif()
  gtest_discover_tests(${ARG_NAME}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "${ARG_LABELS}" ${fixtures}
    DISCOVERY_TIMEOUT 60)
endfunction()
