# Which SUNDIALS the project links (issue 15). Debian's libsundials-dev 6.4.1 is built without
# optimisation, so scripts/build_sundials.sh (run by scripts/setup.sh) builds the same version
# from Debian's source package with -O3 -DNDEBUG as static libraries into a per-user cache, and
# this file prefers that build; Debian's package is the fallback.
#
#   MBSTREAM_SUNDIALS=auto       the optimised build when the cache holds it, else Debian's
#   MBSTREAM_SUNDIALS=optimised  the optimised build, or a configure error
#   MBSTREAM_SUNDIALS=debian     Debian's package (or whatever SUNDIALS_DIR names)
#
# The subdirectories keep their own `find_package(SUNDIALS 6.4 REQUIRED CONFIG)` and link
# SUNDIALS::<module>_shared, the names of Debian's shared libraries. The optimised build has only
# static libraries (SUNDIALS::<module>_static: nothing to find at run time, and no clash with
# Debian's .so.6 of the same soname), so for it each used <module>_shared is made an interface
# target that links <module>_static. SUNDIALS_DIR is set here, so their find_package loads the
# same package (its targets file and aliases skip what exists already).
set(MBSTREAM_SUNDIALS "auto" CACHE STRING
    "SUNDIALS to link: auto (the optimised build of scripts/build_sundials.sh if present, else Debian's), optimised, debian")
set_property(CACHE MBSTREAM_SUNDIALS PROPERTY STRINGS auto optimised debian)

set(mbstream_sundials_modules
    cvode arkode ida nvecserial sunmatrixdense sunmatrixsparse sunlinsoldense sunlinsolklu
    sunnonlinsolfixedpoint sunnonlinsolnewton)

set(mbstream_sundials_prefix "")
if(NOT MBSTREAM_SUNDIALS STREQUAL "debian")
  execute_process(
    COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/../scripts/build_sundials.sh --print-prefix
    OUTPUT_VARIABLE mbstream_sundials_prefix
    OUTPUT_STRIP_TRAILING_WHITESPACE
    RESULT_VARIABLE mbstream_sundials_rc)
  if(NOT mbstream_sundials_rc EQUAL 0
     OR NOT EXISTS "${mbstream_sundials_prefix}/.complete"
     OR NOT EXISTS "${mbstream_sundials_prefix}/lib/cmake/sundials/SUNDIALSConfig.cmake")
    if(MBSTREAM_SUNDIALS STREQUAL "optimised")
      message(FATAL_ERROR "MBSTREAM_SUNDIALS=optimised but the optimised SUNDIALS is not at "
                          "'${mbstream_sundials_prefix}': run scripts/build_sundials.sh")
    endif()
    set(mbstream_sundials_prefix "")
  endif()
endif()

if(mbstream_sundials_prefix)
  set(SUNDIALS_DIR "${mbstream_sundials_prefix}/lib/cmake/sundials"
      CACHE PATH "The directory containing SUNDIALSConfig.cmake" FORCE)
  set(MBSTREAM_SUNDIALS_DIR_SET "${SUNDIALS_DIR}" CACHE INTERNAL "SUNDIALS_DIR as set by MbstreamSundials")
  find_package(SUNDIALS 6.4.1 EXACT REQUIRED CONFIG)
  foreach(module IN LISTS mbstream_sundials_modules)
    if(NOT TARGET SUNDIALS::${module}_shared)
      add_library(SUNDIALS::${module}_shared INTERFACE IMPORTED)
      target_link_libraries(SUNDIALS::${module}_shared INTERFACE SUNDIALS::${module}_static)
    endif()
  endforeach()
  message(STATUS "SUNDIALS: optimised ${SUNDIALS_VERSION} built from Debian's source package "
                 "(-O3 -DNDEBUG, static) in ${mbstream_sundials_prefix}")
else()
  # A SUNDIALS_DIR set above by an earlier configure would win otherwise; one the user gave stays.
  if(DEFINED CACHE{SUNDIALS_DIR} AND SUNDIALS_DIR STREQUAL MBSTREAM_SUNDIALS_DIR_SET)
    unset(SUNDIALS_DIR CACHE)
  endif()
  find_package(SUNDIALS 6.4 REQUIRED CONFIG)
  message(STATUS "SUNDIALS: Debian's libsundials-dev ${SUNDIALS_VERSION} from ${SUNDIALS_DIR} "
                 "(built without optimisation: scripts/build_sundials.sh builds the optimised one)")
endif()
