# ausbau_add_stage(<name> SOURCES ... [LIBS ...]): the executable ausbau-<name>
# from stages/<name>/, linked against the stage runner (ausbau_cli, which
# brings the production layers) and the layers in LIBS (e.g. ausbau_report).
function(ausbau_add_stage name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(ausbau-${name} ${ARG_SOURCES})
  target_link_libraries(ausbau-${name} PRIVATE ausbau_cli ${ARG_LIBS})
endfunction()

# ausbau_add_test(<name> SOURCES ... [LABELS ...]): a GoogleTest executable
# registered with CTest.
function(ausbau_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ausbau_everything GTest::gtest GTest::gtest_main)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS "${ARG_LABELS}"
                       ENVIRONMENT "AUSBAU_BIN_DIR=${CMAKE_BINARY_DIR}/bin" ENVIRONMENT "AUSBAU_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
endfunction()
