# RTL checks as tests: verilator -Wall lint of every module (zero warnings or
# a waiver with a reason in rtl_model/lint.vlt), and Yosys synth_ice40 +
# synth_xilinx of every module (scripts/rtl_synth prints the cell counts).
find_program(YOSYS yosys REQUIRED)
# ceilnav_top uses the generated register package and block (tools/regmap_gen).
add_test(NAME rtl.lint COMMAND ${PROJECT_SOURCE_DIR}/scripts/rtl_lint ${CEILNAV_GENERATED_DIR})
set_tests_properties(rtl.lint PROPERTIES LABELS "unit;rtl")

file(GLOB rtl_modules CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/rtl_model/*.sv)
foreach(sv IN LISTS rtl_modules)
  get_filename_component(module ${sv} NAME_WE)
  if(module MATCHES "_pkg$")
    continue()
  endif()
  add_test(NAME rtl.synth.${module} COMMAND ${PROJECT_SOURCE_DIR}/scripts/rtl_synth ${module} both
                                            ${CEILNAV_GENERATED_DIR})
  set_tests_properties(rtl.synth.${module} PROPERTIES LABELS "slow;rtl" TIMEOUT 900)
endforeach()
