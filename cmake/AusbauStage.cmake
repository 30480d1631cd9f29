# ausbau_add_stage(<name> SOURCES ...): the executable ausbau-<name> from
# stages/<name>/, linked against the common library.
function(ausbau_add_stage name)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  add_executable(ausbau-${name} ${ARG_SOURCES})
  target_link_libraries(ausbau-${name} PRIVATE ausbau_common)
endfunction()

# ausbau_add_test(<name> SOURCES ... [LABELS ...]): a GoogleTest executable
# registered with CTest.
function(ausbau_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ausbau_common GTest::gtest GTest::gtest_main)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS "${ARG_LABELS}"
                       ENVIRONMENT "AUSBAU_BIN_DIR=${CMAKE_BINARY_DIR}/bin" ENVIRONMENT "AUSBAU_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
endfunction()
