# The register block generator on its own (testbench/cosim_regblock_test.cpp):
# a map that uses every generator feature, generated into its own directory at
# configure time (verilate() runs then) with the configure-time build of
# regmap_gen from ceilnav_top.cmake, verilated with and without its optional
# block, each against the generated C++ model.
set(rbtest_map ${CMAKE_CURRENT_LIST_DIR}/regblock_test_map.json)
set(rbtest_gen ${PROJECT_BINARY_DIR}/generated_rbtest)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${rbtest_map})
execute_process(COMMAND ${ceilnav_regmap_boot} ${rbtest_map} ${rbtest_gen}
                RESULT_VARIABLE rbtest_rc)
if(NOT rbtest_rc EQUAL 0)
  message(FATAL_ERROR "could not generate the register block of ${rbtest_map}")
endif()
get_target_property(rbtest_warnings ceilnav_warnings INTERFACE_COMPILE_OPTIONS)
foreach(variant IN ITEMS big small)
  set(name cosim_regblock_${variant}_test)
  add_executable(${name} ${CMAKE_CURRENT_LIST_DIR}/cosim_regblock_test.cpp)
  if(variant STREQUAL big)
    set(prefix Vrbtest_regblock)
    set(params "")
    target_compile_definitions(${name} PRIVATE RBTEST_HAS_EXTRA=1)
  else()
    set(prefix Vrbtest_regblock_small)
    set(params "-GHasExtra=1'b0")
    target_compile_definitions(${name} PRIVATE RBTEST_HAS_EXTRA=0)
  endif()
  verilate(${name} SOURCES ${rbtest_gen}/rbtest_reg_pkg.sv ${rbtest_gen}/rbtest_regblock.sv
           TOP_MODULE rbtest_regblock PREFIX ${prefix}
           VERILATOR_ARGS -Wno-fatal --assert -O3 --x-assign unique --x-initial unique ${params}
           TRACE_FST)
  target_include_directories(${name} PRIVATE ${rbtest_gen} ${CMAKE_CURRENT_LIST_DIR})
  target_link_libraries(${name} PRIVATE ceilnav_stream GTest::gtest GTest::gtest_main)
  target_compile_options(${name} PRIVATE -Wno-unused-parameter)
  set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/cosim_regblock_test.cpp
                              PROPERTIES COMPILE_OPTIONS "${rbtest_warnings}")
  gtest_discover_tests(${name} TEST_PREFIX "${name}." DISCOVERY_TIMEOUT 120
                       PROPERTIES LABELS "cosim")
endforeach()
