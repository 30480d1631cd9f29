# The layer check must fail on an upward include and pass without one:
# cmake -DCHECK=<cmake/CheckLayers.cmake> -DWORK=<dir> -P check_layers_test.cmake
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE ${WORK})
file(WRITE ${WORK}/layers.txt "common/core core\ncommon/planning core planning\nstages/plan core planning\n")
file(WRITE ${WORK}/common/planning/planner.h "#pragma once\n#include \"core/log.h\"\n")
file(WRITE ${WORK}/common/core/log.h "#pragma once\n#include <vector>\n")
file(WRITE ${WORK}/stages/plan/main.cpp "#include \"planning/planner.h\"\n")

execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${WORK} -DLAYERS=${WORK}/layers.txt -P ${CHECK}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "a tree without upward includes was refused:\n${out}")
endif()

# core/ including planning/ (upward), and a second line in a stage's main.
file(WRITE ${WORK}/common/core/log.h "#pragma once\n#include <vector>\n#include \"planning/planner.h\"\n")
file(APPEND ${WORK}/stages/plan/main.cpp "#include \"labeling/labels.h\"\n")
file(WRITE ${WORK}/common/labeling/labels.h "#pragma once\n")
execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${WORK} -DLAYERS=${WORK}/layers.txt -P ${CHECK}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(status EQUAL 0)
  message(FATAL_ERROR "an upward include was not caught:\n${out}")
endif()
foreach(expected "common/core/log.h:3: includes planning/" "stages/plan/main.cpp:2: includes labeling/"
                 "2 include(s) against the layer rule")
  string(FIND "${out}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the report lacks '${expected}':\n${out}")
  endif()
endforeach()
message("layer check: passes a clean tree, reports both upward includes")
