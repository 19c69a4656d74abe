# mbstream_add_test(NAME SOURCES a.cc b.cc LIBS lib1 lib2 [LABELS l1 l2] [TIMEOUT s]
#                   [PROGRAMS mbstream mbstream-server mbstream-viewer])
#
# The one way to declare a GoogleTest suite: builds the executable, links gtest_main and
# registers every test case with ctest. Tests run from the source tree's root so that
# paths such as models/irb1600/irb1600.urdf resolve. PROGRAMS: the project's programs the
# test starts, built before it, their paths in MBSTREAM_CLI, MBSTREAM_SERVER, MBSTREAM_VIEWER.
include(GoogleTest)
find_package(GTest REQUIRED)

function(mbstream_add_test NAME)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;LIBS;LABELS;PROGRAMS" ${ARGN})
  add_executable(${NAME} ${ARG_SOURCES})
  target_link_libraries(${NAME} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gmock GTest::gtest_main)
  target_compile_definitions(${NAME} PRIVATE MBSTREAM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  foreach(program IN LISTS ARG_PROGRAMS)
    if(program STREQUAL "mbstream")
      set(macro MBSTREAM_CLI)
    elseif(program STREQUAL "mbstream-server")
      set(macro MBSTREAM_SERVER)
    elseif(program STREQUAL "mbstream-viewer")
      set(macro MBSTREAM_VIEWER)
    else()
      message(FATAL_ERROR "mbstream_add_test(${NAME}): unknown program ${program}")
    endif()
    target_compile_definitions(${NAME} PRIVATE ${macro}="$<TARGET_FILE:${program}>")
    add_dependencies(${NAME} ${program})
  endforeach()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  gtest_discover_tests(${NAME}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    DISCOVERY_MODE PRE_TEST
    PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "${ARG_LABELS}")
endfunction()
