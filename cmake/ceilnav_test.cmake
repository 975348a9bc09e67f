# ceilnav_add_gtest(<name> SOURCES <src...> LIBS <targets...> [LABELS <labels...>])
# One gtest executable; every TEST() becomes its own ctest entry.
function(ceilnav_add_gtest name)
  if(NOT CEILNAV_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main ceilnav_warnings)
  target_compile_definitions(${name} PRIVATE CEILNAV_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  gtest_discover_tests(${name} TEST_PREFIX "${name}." DISCOVERY_TIMEOUT 120
                       PROPERTIES LABELS "${ARG_LABELS}")
endfunction()

# Every tests/*_test.cpp in the calling directory becomes one gtest executable
# named <prefix>_<file stem>, linked to LIBS.
function(ceilnav_add_gtests_in_dir prefix)
  cmake_parse_arguments(ARG "" "" "LIBS;LABELS" ${ARGN})
  file(GLOB test_sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tests/*_test.cpp)
  foreach(src IN LISTS test_sources)
    get_filename_component(stem ${src} NAME_WE)
    ceilnav_add_gtest(${prefix}_${stem} SOURCES ${src} LIBS ${ARG_LIBS} LABELS ${ARG_LABELS})
  endforeach()
endfunction()
