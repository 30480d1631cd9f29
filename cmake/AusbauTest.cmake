# ausbau_add_test(NAME <name> SOURCES <file> ... LINK <target> ...
#                 [LABELS <label> ...] [RUNS <stage> ...])
#
# One GoogleTest executable, registered with CTest test by test (its
# TEST()s are the CTest names; the executable's name only names the file).
# Modelled on COLMAP's COLMAP_ADD_TEST: the test links only what LINK names
# (the lowest layers that hold what it tests, e.g. ausbau_core for a test of
# core/) besides GoogleTest and the helpers in tests/test_scenes.h
# (ausbau_test_support, which links no layer), so that a test of a low layer
# neither needs nor waits for the layers above it. LINK is required.
#
# The convention (docs/testing.md "Where the test of a file is"): the test
# of common/<layer>/<file>.h is tests/<layer>/test_<file>.cpp, named
# test_<layer>_<file>; end-to-end tests of the executables are in tests/e2e/.
#
# RUNS names the stages the test runs (ausbau-<stage>). The target
# ausbau_unit_tests (tests/CMakeLists.txt) builds the unit tests and the
# stages they run, nothing else; `make test-sanitize` builds only that. A
# stage a test runs but does not list is missing there (exit 127, or a
# skipped test where it checks first).
function(ausbau_add_test)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LINK;LABELS;RUNS" ${ARGN})
  if(NOT ARG_NAME OR NOT ARG_SOURCES)
    message(FATAL_ERROR "ausbau_add_test: NAME and SOURCES are required")
  endif()
  if(NOT ARG_LINK)
    message(FATAL_ERROR "ausbau_add_test(${ARG_NAME}): LINK names the layers the test needs (e.g. ausbau_core)")
  endif()
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "ausbau_add_test(${ARG_NAME}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  set(name ${ARG_NAME})
  foreach(label IN LISTS ARG_LABELS)
    set_property(GLOBAL APPEND PROPERTY AUSBAU_TARGETS_${label} ${name})
    foreach(stage IN LISTS ARG_RUNS)
      set_property(GLOBAL APPEND PROPERTY AUSBAU_TARGETS_${label} ausbau-${stage})
    endforeach()
  endforeach()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LINK} ausbau_test_support GTest::gtest GTest::gtest_main)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS "${ARG_LABELS}"
                       ENVIRONMENT "AUSBAU_BIN_DIR=${CMAKE_BINARY_DIR}/bin" ENVIRONMENT "AUSBAU_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
endfunction()
