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
