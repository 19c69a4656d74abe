# Compiler settings shared by every target: warnings, ccache, release flags.

find_program(MBSTREAM_CCACHE ccache)
if(MBSTREAM_CCACHE)
  set(CMAKE_C_COMPILER_LAUNCHER ${MBSTREAM_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${MBSTREAM_CCACHE})
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
