# Unity builds: each target's C++ files are compiled in batches of MBSTREAM_UNITY_BATCH, one
# translation unit including several .cc files, so that the heavy headers every unit pulls in
# (gRPC and protobuf's generated code, Eigen, GoogleTest) are parsed and instantiated once
# per batch instead of once per file. Measured: seven server/service files cost 47 s of CPU one
# by one and 12 s as one batch (docs/performance.md, "Build").
#
# Unlike CMake's own UNITY_BUILD, a batch includes its files by their path below the source
# root (#include "server/service/watch_run.cc", found through -I${PROJECT_SOURCE_DIR}): two
# checkouts then compile the same text, and ccache (CCACHE_BASEDIR: scripts/build_env.sh)
# shares the objects between them as it does without batches.
#
# Not batched: generated files (protobuf), files with their own compile options, files outside
# the source tree, and the files of cmake/unity_alone.txt (names that clash with a
# neighbour's in an anonymous namespace; each line says which).
#
# A batch must compile to what its files compile to alone. Before any batched target compiles,
# cmake/unity_check.py (the target mbstream_unity_check, run again whenever a batched file
# changes) reads every batch and stops the build when two of its files declare one name with
# internal linkage (an anonymous namespace, static, a const variable: a redefinition error, or
# an overload set that could change which helper a call picks), define a function of one name
# in nested namespaces, or when a file's using-directive or macro reaches the files after it.
# Its message names the files and the fix: a rename, or a line in cmake/unity_alone.txt
# (docs/contributing.md, "Unity builds").

option(MBSTREAM_UNITY_BUILD "Compile each target's files in batches (faster cold builds)" ON)
set(MBSTREAM_UNITY_BATCH 8 CACHE STRING "Files per unity batch (MBSTREAM_UNITY_BUILD)")

# Batches the C++ files of target TARGET (see above).
function(mbstream_unity_target TARGET)
  get_target_property(type ${TARGET} TYPE)
  if(NOT type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|OBJECT_LIBRARY|MODULE_LIBRARY|EXECUTABLE)$")
    return()
  endif()
  get_target_property(sources ${TARGET} SOURCES)
  get_target_property(source_dir ${TARGET} SOURCE_DIR)
  if(NOT sources)
    return()
  endif()
  set(kept)
  set(batched)
  foreach(source IN LISTS sources)
    if(source MATCHES "^\\$<" OR NOT source MATCHES "\\.(cc|cpp|cxx)$")
      list(APPEND kept ${source})
      continue()
    endif()
    cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY ${source_dir} NORMALIZE OUTPUT_VARIABLE path)
    get_source_file_property(generated ${path} TARGET_DIRECTORY ${TARGET} GENERATED)
    get_source_file_property(options ${path} TARGET_DIRECTORY ${TARGET} COMPILE_OPTIONS)
    get_source_file_property(definitions ${path} TARGET_DIRECTORY ${TARGET} COMPILE_DEFINITIONS)
    cmake_path(IS_PREFIX PROJECT_SOURCE_DIR ${path} NORMALIZE inside)
    file(RELATIVE_PATH relative ${PROJECT_SOURCE_DIR} ${path})
    if(generated OR options OR definitions OR NOT inside OR relative IN_LIST MBSTREAM_UNITY_ALONE)
      list(APPEND kept ${source})
    else()
      list(APPEND batched ${relative})
    endif()
  endforeach()
  file(GLOB stale ${CMAKE_BINARY_DIR}/unity/${TARGET}/batch_*.cc)
  list(LENGTH batched count)
  if(count LESS 2)
    if(stale)
      file(REMOVE ${stale})
    endif()
    return()
  endif()
  set(units)
  set(index 0)
  set(content "")
  set(in_batch 0)
  foreach(relative IN LISTS batched)
    string(APPEND content "#include \"${relative}\"\n")
    math(EXPR in_batch "${in_batch} + 1")
    if(in_batch EQUAL MBSTREAM_UNITY_BATCH)
      set(unit ${CMAKE_BINARY_DIR}/unity/${TARGET}/batch_${index}.cc)
      file(CONFIGURE OUTPUT ${unit} CONTENT "${content}" @ONLY)
      list(APPEND units ${unit})
      math(EXPR index "${index} + 1")
      set(content "")
      set(in_batch 0)
    endif()
  endforeach()
  if(in_batch GREATER 0)
    set(unit ${CMAKE_BINARY_DIR}/unity/${TARGET}/batch_${index}.cc)
    file(CONFIGURE OUTPUT ${unit} CONTENT "${content}" @ONLY)
    list(APPEND units ${unit})
  endif()
  list(REMOVE_ITEM stale ${units})  # batches of a longer list of files before
  if(stale)
    file(REMOVE ${stale})
  endif()
  set_property(TARGET ${TARGET} PROPERTY SOURCES ${kept} ${units})
  target_include_directories(${TARGET} PRIVATE ${PROJECT_SOURCE_DIR})
  list(TRANSFORM batched PREPEND ${PROJECT_SOURCE_DIR}/)
  set_property(GLOBAL APPEND PROPERTY MBSTREAM_UNITY_TARGETS ${TARGET})
  set_property(GLOBAL APPEND PROPERTY MBSTREAM_UNITY_UNITS ${units})
  set_property(GLOBAL APPEND PROPERTY MBSTREAM_UNITY_SOURCES ${batched})
endfunction()

# The check of every batch (see above): one step that the batched targets wait for.
function(mbstream_unity_check)
  get_property(targets GLOBAL PROPERTY MBSTREAM_UNITY_TARGETS)
  get_property(units GLOBAL PROPERTY MBSTREAM_UNITY_UNITS)
  get_property(sources GLOBAL PROPERTY MBSTREAM_UNITY_SOURCES)
  if(NOT units)
    return()
  endif()
  find_package(Python3 COMPONENTS Interpreter)
  if(NOT Python3_Interpreter_FOUND)
    message(WARNING "No Python 3: the unity batches are not checked for shared names "
                    "(cmake/unity_check.py); scripts/setup.sh installs python3")
    return()
  endif()
  set(stamp ${CMAKE_BINARY_DIR}/unity/unity_check.stamp)
  add_custom_command(OUTPUT ${stamp}
    COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/cmake/unity_check.py
      ${PROJECT_SOURCE_DIR} ${stamp} ${units}
    DEPENDS ${PROJECT_SOURCE_DIR}/cmake/unity_check.py ${units} ${sources}
    COMMENT "Checking the unity batches for names their files would share (cmake/unity_check.py)"
    VERBATIM)
  add_custom_target(mbstream_unity_check ALL DEPENDS ${stamp})
  foreach(target IN LISTS targets)
    add_dependencies(${target} mbstream_unity_check)
  endforeach()
endfunction()

# Batches every target defined in DIRECTORY and below (called once, at the end of the top-level
# CMakeLists.txt, when every target has its sources), then checks the batches.
function(mbstream_unity_directory DIRECTORY)
  if(NOT MBSTREAM_UNITY_BUILD)
    return()
  endif()
  mbstream_unity_walk(${DIRECTORY})
  mbstream_unity_check()
endfunction()

function(mbstream_unity_walk DIRECTORY)
  if(NOT DEFINED MBSTREAM_UNITY_ALONE)
    # An edit of the list configures again.
    set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
                 ${PROJECT_SOURCE_DIR}/cmake/unity_alone.txt)
    file(STRINGS ${PROJECT_SOURCE_DIR}/cmake/unity_alone.txt lines)
    set(MBSTREAM_UNITY_ALONE)
    foreach(line IN LISTS lines)
      string(REGEX REPLACE "#.*" "" line "${line}")
      string(STRIP "${line}" line)
      if(line)
        list(APPEND MBSTREAM_UNITY_ALONE ${line})
      endif()
    endforeach()
  endif()
  get_property(targets DIRECTORY ${DIRECTORY} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    mbstream_unity_target(${target})
  endforeach()
  get_property(subdirectories DIRECTORY ${DIRECTORY} PROPERTY SUBDIRECTORIES)
  foreach(subdirectory IN LISTS subdirectories)
    mbstream_unity_walk(${subdirectory})
  endforeach()
endfunction()
