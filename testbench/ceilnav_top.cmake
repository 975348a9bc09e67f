# The Verilated device top (rtl_model/ceilnav_top.sv and the blocks under it)
# as a static library: linked by the top co-simulation test and by the host
# (a later RtlBus). The register package and register block come from
# tools/regmap_gen.
# The generated register package comes first (the RTL uses its types), then
# the generated register block.
set(ceilnav_top_sv
    ${CEILNAV_GENERATED_DIR}/ceilnav_widths_pkg.sv
    ${CEILNAV_GENERATED_DIR}/ceilnav_reg_pkg.sv ${CEILNAV_RTL_DIR}/ceilnav_pkg.sv ${CEILNAV_GENERATED_DIR}/ceilnav_regblock.sv
    ${CEILNAV_RTL_DIR}/ceilnav_top.sv ${CEILNAV_RTL_DIR}/pipeline.sv
    ${CEILNAV_RTL_DIR}/frame_check.sv ${CEILNAV_RTL_DIR}/thresh_lut.sv
    ${CEILNAV_RTL_DIR}/histogram.sv ${CEILNAV_RTL_DIR}/moment_gen.sv
    ${CEILNAV_RTL_DIR}/class_moments.sv
    ${CEILNAV_RTL_DIR}/run_fifo.sv ${CEILNAV_RTL_DIR}/run_scanner.sv)
# verilate() runs Verilator at configure time, before the build generates the
# register block: in a fresh build tree, generate it now with a configure-time
# build of the same generator (the build-time rule regenerates it from then on).
# Also when the map or the generator changed since: Verilator must not see a
# stale register block at configure time (an existing build tree after a merge).
set(regmap_gen_sources ${PROJECT_SOURCE_DIR}/tools/regmap_gen.cpp
                       ${PROJECT_SOURCE_DIR}/tools/regmap_model.cpp
                       ${PROJECT_SOURCE_DIR}/tools/regmap_model.hpp
                       ${PROJECT_SOURCE_DIR}/tools/regblock_emit.cpp
                       ${PROJECT_SOURCE_DIR}/fixedpoint/datapath.hpp)
set(regmap_stamp ${CEILNAV_GENERATED_DIR}/ceilnav_regblock.sv)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
             ${PROJECT_SOURCE_DIR}/rtl_model/regmap.json ${regmap_gen_sources})
# The configure-time generator: rebuilt when a generator source changed.
set(ceilnav_regmap_boot ${CMAKE_CURRENT_BINARY_DIR}/regmap_gen_configure)
set(regmap_boot_stale FALSE)
foreach(input IN LISTS regmap_gen_sources)
  if(NOT EXISTS ${ceilnav_regmap_boot} OR ${input} IS_NEWER_THAN ${ceilnav_regmap_boot})
    set(regmap_boot_stale TRUE)
  endif()
endforeach()
if(regmap_boot_stale)
  get_target_property(json_inc nlohmann_json::nlohmann_json INTERFACE_INCLUDE_DIRECTORIES)
  set(json_flags "")
  foreach(dir IN LISTS json_inc)
    list(APPEND json_flags -I${dir})
  endforeach()
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -std=c++20 ${json_flags} -I${PROJECT_SOURCE_DIR}
                          ${PROJECT_SOURCE_DIR}/tools/regmap_gen.cpp
                          ${PROJECT_SOURCE_DIR}/tools/regmap_model.cpp
                          ${PROJECT_SOURCE_DIR}/tools/regblock_emit.cpp -o ${ceilnav_regmap_boot}
                  RESULT_VARIABLE regmap_boot_rc)
  if(NOT regmap_boot_rc EQUAL 0)
    message(FATAL_ERROR "could not build the register map generator at configure time")
  endif()
endif()
if(regmap_boot_stale OR NOT EXISTS ${regmap_stamp}
   OR ${PROJECT_SOURCE_DIR}/rtl_model/regmap.json IS_NEWER_THAN ${regmap_stamp})
  execute_process(COMMAND ${ceilnav_regmap_boot} ${PROJECT_SOURCE_DIR}/rtl_model/regmap.json
                          ${CEILNAV_GENERATED_DIR} RESULT_VARIABLE regmap_gen_rc)
  if(NOT regmap_gen_rc EQUAL 0)
    message(FATAL_ERROR "could not generate the register block at configure time")
  endif()
  # write_if_changed keeps an unchanged file's time: mark the stamp fresh.
  file(TOUCH ${regmap_stamp})
endif()
add_library(ceilnav_rtl_top STATIC)
verilate(ceilnav_rtl_top SOURCES ${ceilnav_top_sv} TOP_MODULE ceilnav_top PREFIX Vceilnav_top
         INCLUDE_DIRS ${CEILNAV_GENERATED_DIR} ${CEILNAV_VERILATOR_COVERAGE}
         VERILATOR_ARGS -Wno-fatal --assert -O3 --x-assign unique --x-initial unique
         TRACE_FST)
add_dependencies(ceilnav_rtl_top ceilnav_regs_gen)
# Verilator's generated code is not ours: no project warnings on it.
target_compile_options(ceilnav_rtl_top PRIVATE -Wno-unused-parameter)
set_target_properties(ceilnav_rtl_top PROPERTIES POSITION_INDEPENDENT_CODE ON)

# The tape configuration (regmap.json "configurations"; docs/registers.md):
# the top's parameter per optional block from the same JSON the register
# generator and the C++ model (regs::kConfigTape) read.
file(READ ${PROJECT_SOURCE_DIR}/rtl_model/regmap.json ceilnav_regmap_text)
function(ceilnav_config_parameters config out)
  string(JSON nconf LENGTH "${ceilnav_regmap_text}" configurations)
  math(EXPR last "${nconf} - 1")
  set(found FALSE)
  foreach(i RANGE ${last})
    string(JSON name GET "${ceilnav_regmap_text}" configurations ${i} name)
    if(name STREQUAL config)
      set(found TRUE)
      string(JSON blocks GET "${ceilnav_regmap_text}" configurations ${i} blocks)
    endif()
  endforeach()
  if(NOT found)
    message(FATAL_ERROR "regmap.json: no configuration ${config}")
  endif()
  # class_moments -> -GHasClassMoments=1'b0/1'b1
  set(args "")
  string(JSON nopt LENGTH "${ceilnav_regmap_text}" optional_blocks)
  math(EXPR olast "${nopt} - 1")
  foreach(i RANGE ${olast})
    string(JSON block GET "${ceilnav_regmap_text}" optional_blocks ${i})
    string(REPLACE "_" ";" words ${block})
    set(camel "")
    foreach(w IN LISTS words)
      string(SUBSTRING ${w} 0 1 first)
      string(TOUPPER ${first} first)
      string(SUBSTRING ${w} 1 -1 rest)
      string(APPEND camel ${first}${rest})
    endforeach()
    string(FIND "${blocks}" "\"${block}\"" at)
    if(at EQUAL -1)
      list(APPEND args "-GHas${camel}=1'b0")
    else()
      list(APPEND args "-GHas${camel}=1'b1")
    endif()
  endforeach()
  set(${out} ${args} PARENT_SCOPE)
endfunction()
ceilnav_config_parameters(tape ceilnav_tape_parameters)
add_library(ceilnav_rtl_top_tape STATIC)
verilate(ceilnav_rtl_top_tape SOURCES ${ceilnav_top_sv} TOP_MODULE ceilnav_top
         PREFIX Vceilnav_top_tape INCLUDE_DIRS ${CEILNAV_GENERATED_DIR} ${CEILNAV_VERILATOR_COVERAGE}
         VERILATOR_ARGS -Wno-fatal --assert -O3 --x-assign unique --x-initial unique
                        ${ceilnav_tape_parameters}
         TRACE_FST)
add_dependencies(ceilnav_rtl_top_tape ceilnav_regs_gen)
target_compile_options(ceilnav_rtl_top_tape PRIVATE -Wno-unused-parameter)

# The same RTL verilated for speed, for the throughput benchmark (bench/): no
# assertions, no trace support, X resolved the fast way (the benchmark resets
# the device and checks its results). Co-simulation keeps ceilnav_rtl_top.
if(CEILNAV_BUILD_BENCHMARKS)
  add_library(ceilnav_rtl_top_fast STATIC)
  verilate(ceilnav_rtl_top_fast SOURCES ${ceilnav_top_sv} TOP_MODULE ceilnav_top
           PREFIX Vceilnav_top_fast INCLUDE_DIRS ${CEILNAV_GENERATED_DIR}
           VERILATOR_ARGS -Wno-fatal -O3 --x-assign fast --x-initial fast)
  add_dependencies(ceilnav_rtl_top_fast ceilnav_regs_gen)
  target_compile_options(ceilnav_rtl_top_fast PRIVATE -Wno-unused-parameter)
endif()

# Co-simulation: Vceilnav_top against stream::CeilnavTop on every port, every cycle.
add_executable(cosim_ceilnav_top_test ${CMAKE_CURRENT_LIST_DIR}/cosim_ceilnav_top_test.cpp)
target_link_libraries(cosim_ceilnav_top_test PRIVATE ceilnav_rtl_top ceilnav_stream ceilnav_regs
                                                     ceilnav_golden ceilnav_warnings GTest::gtest
                                                     GTest::gtest_main)
gtest_discover_tests(cosim_ceilnav_top_test TEST_PREFIX "cosim_ceilnav_top_test."
                     DISCOVERY_TIMEOUT 120 PROPERTIES LABELS "cosim")

# The same top co-simulation in the tape configuration (no class_moments).
add_executable(cosim_ceilnav_top_tape_test ${CMAKE_CURRENT_LIST_DIR}/cosim_ceilnav_top_test.cpp)
target_compile_definitions(cosim_ceilnav_top_tape_test PRIVATE CEILNAV_TOP_CONFIG_TAPE=1)
target_link_libraries(cosim_ceilnav_top_tape_test PRIVATE ceilnav_rtl_top_tape ceilnav_stream
                                                          ceilnav_regs ceilnav_golden
                                                          ceilnav_warnings GTest::gtest
                                                          GTest::gtest_main)
gtest_discover_tests(cosim_ceilnav_top_tape_test TEST_PREFIX "cosim_ceilnav_top_tape_test."
                     DISCOVERY_TIMEOUT 120 PROPERTIES LABELS "cosim")

# Malformed video streams: one co-simulation per class, device level.
add_executable(cosim_malformed_test ${CMAKE_CURRENT_LIST_DIR}/cosim_malformed_test.cpp)
target_link_libraries(cosim_malformed_test PRIVATE ceilnav_rtl_top ceilnav_stream ceilnav_regs
                                                   ceilnav_warnings GTest::gtest GTest::gtest_main)
gtest_discover_tests(cosim_malformed_test TEST_PREFIX "cosim_malformed_test."
                     DISCOVERY_TIMEOUT 120 PROPERTIES LABELS "cosim")

# Register faults: bus errors, read-only writes, LUT and config changes, double buffering.
add_executable(cosim_register_faults_test ${CMAKE_CURRENT_LIST_DIR}/cosim_register_faults_test.cpp)
target_link_libraries(cosim_register_faults_test PRIVATE ceilnav_rtl_top ceilnav_stream ceilnav_regs
                                                         ceilnav_warnings GTest::gtest
                                                         GTest::gtest_main)
gtest_discover_tests(cosim_register_faults_test TEST_PREFIX "cosim_register_faults_test."
                     DISCOVERY_TIMEOUT 120 PROPERTIES LABELS "cosim")

# The malformed-stream and register-fault co-sims in the tape configuration.
foreach(test IN ITEMS malformed register_faults)
  add_executable(cosim_${test}_tape_test ${CMAKE_CURRENT_LIST_DIR}/cosim_${test}_test.cpp)
  target_compile_definitions(cosim_${test}_tape_test PRIVATE CEILNAV_TOP_CONFIG_TAPE=1)
  target_link_libraries(cosim_${test}_tape_test PRIVATE ceilnav_rtl_top_tape ceilnav_stream
                                                        ceilnav_regs ceilnav_warnings GTest::gtest
                                                        GTest::gtest_main)
  gtest_discover_tests(cosim_${test}_tape_test TEST_PREFIX "cosim_${test}_tape_test."
                       DISCOVERY_TIMEOUT 120 PROPERTIES LABELS "cosim")
endforeach()
