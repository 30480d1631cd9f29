# ausbau_add_stage(<name> SOURCES ... [LIBS ...]): the executable ausbau-<name>
# from stages/<name>/, linked against the stage runner (ausbau_cli, which
# brings the production layers) and the layers in LIBS (e.g. ausbau_report).
# Every stage is installed (cmake/AusbauInstall.cmake: `cmake --install`,
# the Debian package).
function(ausbau_add_stage name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(ausbau-${name} ${ARG_SOURCES})
  target_link_libraries(ausbau-${name} PRIVATE ausbau_cli ${ARG_LIBS})
  install(TARGETS ausbau-${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()

# ausbau_add_test(<name> SOURCES ... [LABELS ...] [RUNS <stage> ...]): a
# GoogleTest executable registered with CTest. RUNS names the stages it runs
# (ausbau-<stage>). The target ausbau_unit_tests (tests/CMakeLists.txt)
# builds the unit tests and the stages they run, nothing else; `make
# test-sanitize` builds only that. A stage a test runs but does not list is
# missing there (exit 127, or a skipped test where it checks first).
function(ausbau_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LABELS;RUNS" ${ARGN})
  foreach(label IN LISTS ARG_LABELS)
    set_property(GLOBAL APPEND PROPERTY AUSBAU_TARGETS_${label} ${name})
    foreach(stage IN LISTS ARG_RUNS)
      set_property(GLOBAL APPEND PROPERTY AUSBAU_TARGETS_${label} ausbau-${stage})
    endforeach()
  endforeach()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ausbau_everything GTest::gtest GTest::gtest_main)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS "${ARG_LABELS}"
                       ENVIRONMENT "AUSBAU_BIN_DIR=${CMAKE_BINARY_DIR}/bin" ENVIRONMENT "AUSBAU_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
endfunction()
