# cmake -DSOURCE_DIR=<tree> -DLAYERS=<layers.txt> -P cmake/CheckLayers.cmake
#
# Two rules (ARCHITECTURE.md "Layers"):
#
# 1. The fixed layer order below. A layer may link only layers before it in
#    AUSBAU_LAYER_ORDER; the link table (cmake/LayerTable.cmake, written from
#    the build's link graph) is checked against it, so a new downward link
#    that turns the order around fails here, not months later as a cycle.
# 2. No upward include. A file under common/<layer>/ or stages/<stage>/ may
#    include a project header ("<folder>/x.h") only of a layer its target
#    links. Every include form counts: "x/y.h" and <x/y.h>, spaces or tabs
#    around '#', `#include_next`, and a path written "./x/y.h" or "../x/y.h".
#    Only the first folder of the path decides, and only folders that are
#    layers (common/<folder>) are checked: <vector> or <Eigen/Dense> are not.
#
# Fails (exit 1) and prints each offending line as file:line.
cmake_minimum_required(VERSION 3.20)
if(NOT SOURCE_DIR OR NOT LAYERS)
  message(FATAL_ERROR "usage: cmake -DSOURCE_DIR=... -DLAYERS=.../layers.txt -P CheckLayers.cmake")
endif()

# Lowest first; the same order as common/CMakeLists.txt and ARCHITECTURE.md.
# `fixtures` sits beside the production layers (linked by tests, benchmarks
# and ausbau-scene-gen only), so it is last. A layer not listed here (a new
# folder) is an error: put it in its place in the order.
set(AUSBAU_LAYER_ORDER core geometry scene cad artifact collision labeling planning inistate report
                       workflow cli fixtures)
if(DEFINED LAYER_ORDER)  # the test of this script gives its own
  set(AUSBAU_LAYER_ORDER ${LAYER_ORDER})
endif()

file(STRINGS ${LAYERS} rows)
file(GLOB layer_dirs RELATIVE ${SOURCE_DIR}/common ${SOURCE_DIR}/common/*)
set(violations 0)
set(checked 0)

# Rule 1: each layer links only layers below it in the order.
foreach(row IN LISTS rows)
  string(REPLACE " " ";" fields "${row}")
  list(POP_FRONT fields dir)
  if(NOT dir MATCHES "^common/(.+)$")
    continue()
  endif()
  set(layer ${CMAKE_MATCH_1})
  list(FIND AUSBAU_LAYER_ORDER ${layer} own_rank)
  if(own_rank EQUAL -1)
    message("${dir}: layer '${layer}' is not in the layer order (cmake/CheckLayers.cmake AUSBAU_LAYER_ORDER)")
    math(EXPR violations "${violations} + 1")
    continue()
  endif()
  foreach(linked IN LISTS fields)
    list(FIND AUSBAU_LAYER_ORDER ${linked} rank)
    if(rank GREATER own_rank)
      message("${dir}: links ${linked}, which comes after ${layer} in the layer order (${AUSBAU_LAYER_ORDER})")
      math(EXPR violations "${violations} + 1")
    endif()
  endforeach()
endforeach()

# Rule 2: no include of a layer the target does not link, in any form.
set(include_form "^[ \t]*#[ \t]*include(_next)?[ \t]*[<\"](\\./|\\.\\./)*([A-Za-z0-9_]+)/")
foreach(row IN LISTS rows)
  string(REPLACE " " ";" fields "${row}")
  list(POP_FRONT fields dir)
  set(allowed ${fields})
  file(GLOB_RECURSE sources ${SOURCE_DIR}/${dir}/*.h ${SOURCE_DIR}/${dir}/*.hpp ${SOURCE_DIR}/${dir}/*.cpp
       ${SOURCE_DIR}/${dir}/*.cc ${SOURCE_DIR}/${dir}/*.inc)
  foreach(source IN LISTS sources)
    math(EXPR checked "${checked} + 1")
    file(STRINGS ${source} lines)
    set(number 0)
    foreach(line IN LISTS lines)
      math(EXPR number "${number} + 1")
      if(line MATCHES "${include_form}")
        set(layer ${CMAKE_MATCH_3})
        if(layer IN_LIST layer_dirs AND NOT layer IN_LIST allowed)
          file(RELATIVE_PATH shown ${SOURCE_DIR} ${source})
          message("${shown}:${number}: includes ${layer}/, which ${dir} does not link (it may include: ${allowed})")
          math(EXPR violations "${violations} + 1")
        endif()
      endif()
    endforeach()
  endforeach()
endforeach()
if(violations GREATER 0)
  message(FATAL_ERROR "${violations} violation(s) of the layer rule (ARCHITECTURE.md \"Layers\")")
endif()
message("layer rule: ${checked} files checked, no upward include, links follow the layer order")
