# The co-simulation build functions (testbench/CMakeLists.txt, docs/cosim.md
# "The scaffolding"): Verilator runs in one place with one set of flags.

# ceilnav_verilate(<target> TOP <module> SV <files...> [PREFIX <class>]
#                  [FAST] [INCLUDE_DIRS <dirs...>] [ARGS <verilator args...>])
# Verilates TOP from SV into <target> (an executable or a library), as the
# class PREFIX (default V<module>). The co-simulation flavour: assertions on,
# X resolved "unique" from the seeded random state (registers without reset
# power up random, as in silicon), FST trace support, line and toggle coverage
# in a coverage build (CEILNAV_RTL_COVERAGE). FAST: for speed (no assertions,
# no trace, X resolved "fast"). Verilator's generated code is not ours: no
# project warnings on it.
function(ceilnav_verilate target)
  cmake_parse_arguments(ARG "FAST" "TOP;PREFIX" "SV;INCLUDE_DIRS;ARGS" ${ARGN})
  if(NOT ARG_PREFIX)
    set(ARG_PREFIX V${ARG_TOP})
  endif()
  set(include_dirs "")
  if(ARG_INCLUDE_DIRS)
    set(include_dirs INCLUDE_DIRS ${ARG_INCLUDE_DIRS})
  endif()
  if(ARG_FAST)
    verilate(${target} SOURCES ${ARG_SV} TOP_MODULE ${ARG_TOP} PREFIX ${ARG_PREFIX} ${include_dirs}
             VERILATOR_ARGS -Wno-fatal -O3 --x-assign fast --x-initial fast ${ARG_ARGS})
  else()
    verilate(${target} SOURCES ${ARG_SV} TOP_MODULE ${ARG_TOP} PREFIX ${ARG_PREFIX} ${include_dirs}
             ${CEILNAV_VERILATOR_COVERAGE}
             VERILATOR_ARGS -Wno-fatal --assert -O3 --x-assign unique --x-initial unique ${ARG_ARGS}
             TRACE_FST)
  endif()
  target_compile_options(${target} PRIVATE -Wno-unused-parameter)
endfunction()

# ceilnav_add_cosim(<name> SOURCES <cpp...>
#                   (TOP <module> [SV <files...>] [PREFIX <class>] [ARGS <args...>]
#                    [VARIANT <class> <args...>] [VARIANT2 <class> <args...>] | RTL <library>)
#                   [LIBS <libs...>] [DEFINES <defs...>] [INCLUDE_DIRS <dirs...>])
# A GoogleTest co-simulation executable <name>: with TOP, the block verilated
# into it (SV defaults to the list CEILNAV_SV_<module>; VARIANT verilates it
# once more as <class> with other parameters, VARIANT2 a third time); with RTL, linked against an
# already verilated library (the device top). The test sources get the
# project warnings; every TEST becomes a ctest entry "<name>.<suite>.<test>"
# labelled cosim.
function(ceilnav_add_cosim name)
  cmake_parse_arguments(ARG "" "TOP;PREFIX;RTL" "SV;SOURCES;LIBS;ARGS;VARIANT;VARIANT2;DEFINES;INCLUDE_DIRS"
                        ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  if(ARG_TOP)
    if(NOT ARG_SV)
      set(ARG_SV ${CEILNAV_SV_${ARG_TOP}})
    endif()
    set(prefix "")
    if(ARG_PREFIX)
      set(prefix PREFIX ${ARG_PREFIX})
    endif()
    ceilnav_verilate(${name} TOP ${ARG_TOP} SV ${ARG_SV} ${prefix} ARGS ${ARG_ARGS})
    foreach(variant IN ITEMS ARG_VARIANT ARG_VARIANT2)
      if(${variant})
        set(variant_args ${${variant}})
        list(POP_FRONT variant_args variant_prefix)
        ceilnav_verilate(${name} TOP ${ARG_TOP} SV ${ARG_SV} PREFIX ${variant_prefix}
                         ARGS ${variant_args})
      endif()
    endforeach()
  else()
    list(APPEND ARG_LIBS ${ARG_RTL})
  endif()
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} ceilnav_stream GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE CEILNAV_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                                             ${ARG_DEFINES})
  if(ARG_INCLUDE_DIRS)
    target_include_directories(${name} PRIVATE ${ARG_INCLUDE_DIRS})
  endif()
  # Our own test code is held to the project's warnings (the Verilated code
  # in the same target is not).
  get_target_property(warnings ceilnav_warnings INTERFACE_COMPILE_OPTIONS)
  set_source_files_properties(${ARG_SOURCES} PROPERTIES COMPILE_OPTIONS "${warnings}")
  gtest_discover_tests(${name} TEST_PREFIX "${name}." DISCOVERY_TIMEOUT 120
                       PROPERTIES LABELS "cosim")
endfunction()

# ceilnav_config_parameters(<configuration> <out var>): the top's parameter per
# optional block (regmap.json "configurations"; docs/registers.md), e.g.
# class_moments -> -GHasClassMoments=1'b0 or 1'b1, from the same JSON the
# register generator and the C++ model (regs::kConfig*) read.
function(ceilnav_config_parameters config out)
  file(READ ${PROJECT_SOURCE_DIR}/rtl_model/regmap.json text)
  string(JSON nconf LENGTH "${text}" configurations)
  math(EXPR last "${nconf} - 1")
  set(found FALSE)
  foreach(i RANGE ${last})
    string(JSON name GET "${text}" configurations ${i} name)
    if(name STREQUAL config)
      set(found TRUE)
      string(JSON blocks GET "${text}" configurations ${i} blocks)
    endif()
  endforeach()
  if(NOT found)
    message(FATAL_ERROR "regmap.json: no configuration ${config}")
  endif()
  set(args "")
  string(JSON nopt LENGTH "${text}" optional_blocks)
  math(EXPR olast "${nopt} - 1")
  foreach(i RANGE ${olast})
    string(JSON block GET "${text}" optional_blocks ${i})
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
