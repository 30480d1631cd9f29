# The layer check must pass a clean tree and fail on an upward include of
# every form, and on a link against the fixed layer order:
# cmake -DCHECK=<cmake/CheckLayers.cmake> -DWORK=<dir> -P check_layers_test.cmake
cmake_minimum_required(VERSION 3.20)
set(order "-DLAYER_ORDER=core;planning;labeling")

function(run_check)
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${WORK} -DLAYERS=${WORK}/layers.txt "${order}" -P ${CHECK}
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  set(status ${status} PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
endfunction()

function(expect_in out)
  foreach(expected IN LISTS ARGN)
    string(FIND "${out}" "${expected}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "the report lacks '${expected}':\n${out}")
    endif()
  endforeach()
endfunction()

file(REMOVE_RECURSE ${WORK})
file(WRITE ${WORK}/layers.txt "common/core core\ncommon/planning core planning\nstages/plan core planning\n")
# Includes that are allowed: downward in both forms, system and third-party
# headers whose first folder is no layer.
file(WRITE ${WORK}/common/planning/planner.h "#pragma once\n#include \"core/log.h\"\n#include <core/log.h>\n")
file(WRITE ${WORK}/common/core/log.h "#pragma once\n#include <vector>\n#include <Eigen/Dense>\n")
file(WRITE ${WORK}/common/labeling/labels.h "#pragma once\n")
file(WRITE ${WORK}/stages/plan/main.cpp "#include \"planning/planner.h\"\n")
run_check()
if(NOT status EQUAL 0)
  message(FATAL_ERROR "a tree without upward includes was refused:\n${out}")
endif()

# Each form of an upward include, one per line of core/log.h (lines 4-9),
# and one in a stage's main (a layer its target does not link).
file(WRITE ${WORK}/common/core/log.h
  "#pragma once\n#include <vector>\n#include <Eigen/Dense>\n"
  "#include \"planning/planner.h\"\n"      # 4: quoted
  "#include <planning/planner.h>\n"        # 5: angle brackets
  "#  include \"planning/planner.h\"\n"    # 6: spaces after '#'
  "  #\tinclude<planning/planner.h>\n"     # 7: indented, a tab, no space before '<'
  "#include_next \"planning/planner.h\"\n" # 8: include_next
  "#include \"../planning/planner.h\"\n")  # 9: a relative path
file(APPEND ${WORK}/stages/plan/main.cpp "#include <labeling/labels.h>\n")
run_check()
if(status EQUAL 0)
  message(FATAL_ERROR "an upward include was not caught:\n${out}")
endif()
expect_in("${out}" "common/core/log.h:4: includes planning/" "common/core/log.h:5: includes planning/"
          "common/core/log.h:6: includes planning/" "common/core/log.h:7: includes planning/"
          "common/core/log.h:8: includes planning/" "common/core/log.h:9: includes planning/"
          "stages/plan/main.cpp:2: includes labeling/" "7 violation(s) of the layer rule")

# A link against the fixed order: core linking planning is refused even
# with no include at all (it would make the order, and later a cycle, wrong).
file(WRITE ${WORK}/common/core/log.h "#pragma once\n")
file(WRITE ${WORK}/stages/plan/main.cpp "#include \"planning/planner.h\"\n")
file(WRITE ${WORK}/layers.txt "common/core core planning\ncommon/planning core planning\nstages/plan core planning\n")
run_check()
if(status EQUAL 0)
  message(FATAL_ERROR "a link against the layer order was not caught:\n${out}")
endif()
expect_in("${out}" "common/core: links planning, which comes after core in the layer order")

# A layer folder missing from the order is refused too.
file(WRITE ${WORK}/layers.txt "common/core core\ncommon/newlayer core newlayer\n")
file(WRITE ${WORK}/common/newlayer/x.h "#pragma once\n")
run_check()
if(status EQUAL 0)
  message(FATAL_ERROR "a layer outside the order was not caught:\n${out}")
endif()
expect_in("${out}" "layer 'newlayer' is not in the layer order")
message("layer check: passes a clean tree; catches 6 include forms, a link against the order, an unordered layer")
