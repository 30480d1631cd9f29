# CMake must refuse a cycle between targets, as the top CMakeLists.txt asks
# (GLOBAL_DEPENDS_NO_CYCLES): a throwaway project with two static libraries
# that link each other fails to configure. The same project without the
# property configures, so the failure is the property's doing, not a broken
# project (CMake accepts cycles of static libraries by default).
# cmake -DWORK=<dir> -P refuses_cycles.cmake
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE ${WORK})

function(configure_project name property)
  set(src ${WORK}/${name}/src)
  file(WRITE ${src}/a.c "int b(void);\nint a(void) { return b(); }\n")
  file(WRITE ${src}/b.c "int a(void);\nint b(void) { return 1; }\n")
  file(WRITE ${src}/CMakeLists.txt
    "cmake_minimum_required(VERSION 3.20)\n"
    "project(cycle LANGUAGES C)\n"
    "${property}\n"
    "add_library(a STATIC a.c)\n"
    "add_library(b STATIC b.c)\n"
    "target_link_libraries(a PUBLIC b)\n"
    "target_link_libraries(b PUBLIC a)\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${src} -B ${WORK}/${name}/build
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  set(status ${status} PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
endfunction()

configure_project(allowed "")
if(NOT status EQUAL 0)
  message(FATAL_ERROR "the cycle project does not configure even without GLOBAL_DEPENDS_NO_CYCLES:\n${out}")
endif()

configure_project(refused "set_property(GLOBAL PROPERTY GLOBAL_DEPENDS_NO_CYCLES ON)")
if(status EQUAL 0)
  message(FATAL_ERROR "CMake accepted two libraries that link each other under GLOBAL_DEPENDS_NO_CYCLES:\n${out}")
endif()
string(FIND "${out}" "cycle" at)
if(at EQUAL -1)
  message(FATAL_ERROR "configure failed, but not because of the cycle:\n${out}")
endif()

# The top CMakeLists.txt must ask for it, or the check above proves nothing.
file(READ ${SOURCE_DIR}/CMakeLists.txt top)
if(NOT top MATCHES "set_property\\(GLOBAL PROPERTY GLOBAL_DEPENDS_NO_CYCLES ON\\)")
  message(FATAL_ERROR "${SOURCE_DIR}/CMakeLists.txt does not set GLOBAL_DEPENDS_NO_CYCLES")
endif()
message("cycles: CMake refuses two libraries that link each other; the project asks it to")
