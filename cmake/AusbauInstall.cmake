# What `cmake --install` puts where (and so the Debian package, `make
# package`): the stages (ausbau_add_stage installs each) in bin/, beside
# them `ausbau-run` (one scene through the pipeline, scripts/ausbau-run.in),
# the Makefile pipelines and the two scripts they call in share/ausbau/ (the
# same layout as the source tree: pipelines/ and scripts/ side by side, so
# their relative paths hold), the docs in share/doc/ausbau/. Nothing of the
# tests, benchmarks or fixtures: ausbau-scene-gen is a stage and is there.
install(DIRECTORY ${CMAKE_SOURCE_DIR}/pipelines/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ausbau/pipelines
        PATTERN "__pycache__" EXCLUDE)
install(PROGRAMS ${CMAKE_SOURCE_DIR}/scripts/timed.sh ${CMAKE_SOURCE_DIR}/scripts/verdict-table.sh
        DESTINATION ${CMAKE_INSTALL_DATADIR}/ausbau/scripts)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ausbau/scenes)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/schemas/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/schemas)
install(FILES ${CMAKE_SOURCE_DIR}/README.md ${CMAKE_SOURCE_DIR}/ARCHITECTURE.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
# docs/*.md beside them, as docs/, so the README's links hold in the
# installed tree too (the result files under docs/results/ stay in the repo).
file(GLOB ausbau_docs ${CMAKE_SOURCE_DIR}/docs/*.md)
install(FILES ${ausbau_docs} DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)
# Each stage's README as share/doc/ausbau/stages/<stage>.md.
file(GLOB ausbau_stage_readmes RELATIVE ${CMAKE_SOURCE_DIR}/stages ${CMAKE_SOURCE_DIR}/stages/*/README.md)
foreach(readme IN LISTS ausbau_stage_readmes)
  get_filename_component(stage ${readme} DIRECTORY)
  install(FILES ${CMAKE_SOURCE_DIR}/stages/${readme} DESTINATION ${CMAKE_INSTALL_DOCDIR}/stages RENAME ${stage}.md)
endforeach()
# ausbau-run twice: in the build folder's bin/ with the source tree's
# pipelines, and for the installed tree with those beside it.
set(AUSBAU_RUN_PIPELINES "'${CMAKE_SOURCE_DIR}/pipelines'")
configure_file(${CMAKE_SOURCE_DIR}/scripts/ausbau-run.in ${CMAKE_RUNTIME_OUTPUT_DIRECTORY}/ausbau-run @ONLY)
set(AUSBAU_RUN_PIPELINES "\"$bin/../${CMAKE_INSTALL_DATADIR}/ausbau/pipelines\"")
configure_file(${CMAKE_SOURCE_DIR}/scripts/ausbau-run.in ${CMAKE_BINARY_DIR}/install/ausbau-run @ONLY)
install(PROGRAMS ${CMAKE_BINARY_DIR}/install/ausbau-run DESTINATION ${CMAKE_INSTALL_BINDIR})

# The Debian package (CPack's DEB generator): `make package` or `cpack -G DEB`
# in the build folder. The shared libraries it needs are found by
# dpkg-shlibdeps (package dpkg-dev, which scripts/install-deps.sh installs);
# make runs the pipelines.
set(CPACK_GENERATOR "DEB")
set(CPACK_PACKAGE_NAME "ausbau")
set(CPACK_PACKAGE_VENDOR "Ausbau")
set(CPACK_PACKAGE_CONTACT "Ausbau developers <ausbau@invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "disassembly planning for CAD parts: a path out of the surroundings, or why none")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "make")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-numpy, snakemake")
include(CPack)
