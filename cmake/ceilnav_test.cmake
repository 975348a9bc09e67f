# Test labels. Every test carries exactly one speed class:
#   unit  - fast checks of one layer (no Verilated RTL simulation), seconds in all;
#   cosim - Verilated RTL against the C++ model;
#   slow  - anything that takes more than a few seconds (synthesis, the accuracy
#           study, the CLI end to end, benchmark smoke runs).
# Extra labels say what a test is about (rtl, cli, accuracy, bench).
# `ctest --preset unit` (scripts/test --unit) runs label unit alone.

# ceilnav_add_gtest(<name> SOURCES <src...> LIBS <targets...> [LABELS <labels...>]
#                   [SLOW <gtest patterns...>])
# One gtest executable; every TEST() becomes its own ctest entry with LABELS,
# except those matching a SLOW pattern (gtest filter syntax, e.g.
# Suite.Test or Suite.*), which are labelled slow instead.
function(ceilnav_add_gtest name)
  if(NOT CEILNAV_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS;SLOW" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main ceilnav_warnings)
  target_compile_definitions(${name} PRIVATE CEILNAV_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  ceilnav_discover_gtests(${name} LABELS ${ARG_LABELS} SLOW ${ARG_SLOW})
endfunction()

# ceilnav_discover_gtests(<target> LABELS <labels...> [SLOW <gtest patterns...>])
# gtest_discover_tests with the slow split above (for targets made elsewhere).
function(ceilnav_discover_gtests target)
  cmake_parse_arguments(ARG "" "" "LABELS;SLOW" ${ARGN})
  if(NOT ARG_SLOW)
    gtest_discover_tests(${target} TEST_PREFIX "${target}." DISCOVERY_TIMEOUT 120
                         PROPERTIES LABELS "${ARG_LABELS}")
    return()
  endif()
  list(JOIN ARG_SLOW ":" slow_filter)
  gtest_discover_tests(${target} TEST_PREFIX "${target}." DISCOVERY_TIMEOUT 120
                       TEST_FILTER "-${slow_filter}" PROPERTIES LABELS "${ARG_LABELS}")
  gtest_discover_tests(${target} TEST_PREFIX "${target}." DISCOVERY_TIMEOUT 120
                       TEST_FILTER "${slow_filter}" PROPERTIES LABELS "slow")
endfunction()

# Every tests/*_test.cpp in the calling directory becomes one gtest executable
# named <prefix>_<file stem>, linked to LIBS; SLOW patterns apply to all of them.
function(ceilnav_add_gtests_in_dir prefix)
  cmake_parse_arguments(ARG "" "" "LIBS;LABELS;SLOW" ${ARGN})
  file(GLOB test_sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tests/*_test.cpp)
  foreach(src IN LISTS test_sources)
    get_filename_component(stem ${src} NAME_WE)
    ceilnav_add_gtest(${prefix}_${stem} SOURCES ${src} LIBS ${ARG_LIBS} LABELS ${ARG_LABELS}
                      SLOW ${ARG_SLOW})
  endforeach()
endfunction()
