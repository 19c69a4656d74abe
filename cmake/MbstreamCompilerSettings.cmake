# Compiler settings shared by every target: warnings, ccache, release flags.

find_program(MBSTREAM_CCACHE ccache)
if(MBSTREAM_CCACHE)
  set(CMAKE_C_COMPILER_LAUNCHER ${MBSTREAM_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${MBSTREAM_CCACHE})
endif()

# LLVM's linker when installed (scripts/setup.sh installs it): it links a test program in a
# fifth of GNU ld's CPU time (service_test under ASan: 0.5 s against 2.4 s), and CI links
# about sixty programs per build.
find_program(MBSTREAM_LLD ld.lld)
if(MBSTREAM_LLD)
  add_link_options(-fuse-ld=lld)
endif()

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()

# Release keeps assert() on (no -DNDEBUG): internal checks stay on in every build.
# Eigen's own per-element bounds checks are switched off for speed (EIGEN_NO_DEBUG);
# mbstream's invariant checks (MBSTREAM_CHECK) are independent of both.
string(REPLACE "-DNDEBUG" "" CMAKE_CXX_FLAGS_RELEASE "${CMAKE_CXX_FLAGS_RELEASE}")
string(REPLACE "-DNDEBUG" "" CMAKE_C_FLAGS_RELEASE "${CMAKE_C_FLAGS_RELEASE}")
string(REPLACE "-DNDEBUG" "" CMAKE_CXX_FLAGS_RELWITHDEBINFO "${CMAKE_CXX_FLAGS_RELWITHDEBINFO}")
add_compile_definitions($<$<CONFIG:Release,RelWithDebInfo>:EIGEN_NO_DEBUG>)

add_compile_options(-Wall -Wextra)
# GCC 12 reports false -Wrestrict positives inside std::string concatenation at -O2/-O3
# (GCC bug 105329); they would turn every error-message builder into a build failure.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  add_compile_options(-Wno-restrict)
endif()
if(MBSTREAM_WERROR)
  add_compile_options(-Werror)
endif()

# Sanitizer builds (CI: scripts/test.sh --ci). MBSTREAM_SANITIZE is a comma-separated list
# given to -fsanitize=, e.g. "address,undefined" or "thread"; each needs its own build
# directory. UBSan findings abort (-fno-sanitize-recover) so that a test fails on them.
# Suppressions and runtime options: cmake/sanitizers/ (docs/reliability.md says why).
set(MBSTREAM_SANITIZE "" CACHE STRING
    "Build with these sanitizers (-fsanitize= list, e.g. address,undefined or thread)")

# libFuzzer targets (fuzz/). Clang only. Every library gets the fuzzer's coverage
# instrumentation (-fsanitize=fuzzer-no-link) and the sanitizers of MBSTREAM_SANITIZE
# (address,undefined when it is empty), so one build directory can also run the test
# suite under ASan + UBSan (fuzz/README.md).
option(MBSTREAM_BUILD_FUZZERS "Build the libFuzzer targets in fuzz/ (clang only)" OFF)
set(mbstream_sanitize_compile "${MBSTREAM_SANITIZE}")
if(MBSTREAM_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "MBSTREAM_BUILD_FUZZERS needs clang: configure with "
                        "-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++")
  endif()
  if(NOT MBSTREAM_SANITIZE)
    set(MBSTREAM_SANITIZE address,undefined CACHE STRING "" FORCE)
  endif()
  set(mbstream_sanitize_compile "fuzzer-no-link,${MBSTREAM_SANITIZE}")
endif()

if(MBSTREAM_SANITIZE)
  if(MBSTREAM_SANITIZE MATCHES "thread" AND MBSTREAM_SANITIZE MATCHES "address")
    message(FATAL_ERROR "MBSTREAM_SANITIZE: thread and address cannot be combined")
  endif()
  if(MBSTREAM_SANITIZE MATCHES "undefined")
    set(mbstream_sanitize_recover -fno-sanitize-recover=all)
  endif()
  # -g1: line tables for readable reports at little compile cost.
  add_compile_options(-fsanitize=${mbstream_sanitize_compile} ${mbstream_sanitize_recover}
                      -fno-omit-frame-pointer -g1)
  add_link_options(-fsanitize=${MBSTREAM_SANITIZE})
endif()
