# cmake -DSOURCE_DIR=<tree> -DLINKS_FILE=<build>/layer_links.txt -P check_layers.cmake
#
# The dependency direction of the libraries (docs/architecture.md, "Libraries"):
#
#   fixedpoint <- common <- stream, golden, host <- drivers <- apps
#
# fixedpoint depends on nothing of the project; common on fixedpoint; stream
# (the bit-true models) on common, fixedpoint and the generated register map;
# golden (floating-point references, renderer) on common and fixedpoint only;
# host (driver and pose maths) on common, fixedpoint and the register map —
# nothing of stream, golden or drivers; drivers (bus backends) on host and
# stream. Two checks, both over the libraries (tests may use any layer):
#   1. every #include "dir/..." in a layer's sources names an allowed layer;
#   2. every project library a layer's library links (LINKS_FILE, written at
#      configure time from the targets' LINK_LIBRARIES) is an allowed layer.
cmake_minimum_required(VERSION 3.25)

# layer -> layers (folders) its sources may include; "ceilnav" is the
# generated register map (ceilnav/regs.hpp).
set(allowed_fixedpoint fixedpoint)
set(allowed_common common fixedpoint)
set(allowed_stream stream common fixedpoint ceilnav)
set(allowed_golden golden common fixedpoint)
set(allowed_host host common fixedpoint ceilnav)
set(allowed_drivers drivers host stream common fixedpoint ceilnav)
set(project_dirs fixedpoint common stream golden host drivers apps testbench bench fuzz tools
                 examples ceilnav)

set(violations "")
foreach(layer IN ITEMS fixedpoint common stream golden host drivers)
  file(GLOB_RECURSE sources ${SOURCE_DIR}/${layer}/*.hpp ${SOURCE_DIR}/${layer}/*.cpp)
  list(FILTER sources EXCLUDE REGEX "/tests/")
  if(sources STREQUAL "")
    message(FATAL_ERROR "layer ${layer}: no sources found under ${SOURCE_DIR}/${layer}")
  endif()
  foreach(src IN LISTS sources)
    file(STRINGS ${src} includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"[^\"/]+/")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[^\"]*\"([^\"/]+)/.*$" "\\1" dir "${line}")
      if(dir IN_LIST project_dirs AND NOT dir IN_LIST allowed_${layer})
        file(RELATIVE_PATH rel ${SOURCE_DIR} ${src})
        list(APPEND violations "${rel} (layer ${layer}) includes ${dir}/")
      endif()
    endforeach()
  endforeach()
endforeach()

# Library -> layer.
set(layer_of_ceilnav_fixedpoint fixedpoint)
set(layer_of_ceilnav_common common)
set(layer_of_ceilnav_regs ceilnav)
set(layer_of_ceilnav_stream stream)
set(layer_of_ceilnav_golden golden)
set(layer_of_ceilnav_golden_pattern golden)
set(layer_of_ceilnav_golden_corridor golden)
set(layer_of_ceilnav_golden_ceiling golden)
set(layer_of_ceilnav_host host)
set(layer_of_ceilnav_host_pattern host)
set(layer_of_ceilnav_host_corridor host)
set(layer_of_ceilnav_host_homing host)
set(layer_of_ceilnav_drivers drivers)
set(allowed_ceilnav fixedpoint)
if(NOT EXISTS ${LINKS_FILE})
  message(FATAL_ERROR "no link graph at ${LINKS_FILE}: configure the build tree first")
endif()
file(STRINGS ${LINKS_FILE} link_lines)
list(LENGTH link_lines nlinks)
if(nlinks LESS 8)
  message(FATAL_ERROR "${LINKS_FILE}: ${nlinks} libraries, expected every layer's")
endif()
foreach(line IN LISTS link_lines)
  string(FIND "${line}" ": " colon)
  if(colon EQUAL -1)
    message(FATAL_ERROR "${LINKS_FILE}: malformed line '${line}'")
  endif()
  string(SUBSTRING "${line}" 0 ${colon} target)
  math(EXPR after "${colon} + 2")
  string(SUBSTRING "${line}" ${after} -1 deps)
  separate_arguments(deps)
  set(layer ${layer_of_${target}})
  foreach(dep IN LISTS deps)
    if(DEFINED layer_of_${dep})
      set(dep_layer ${layer_of_${dep}})
      if(NOT dep_layer STREQUAL layer AND NOT dep_layer IN_LIST allowed_${layer})
        list(APPEND violations "library ${target} (layer ${layer}) links ${dep} (layer ${dep_layer})")
      endif()
    endif()
  endforeach()
endforeach()

if(violations)
  list(JOIN violations "\n  " text)
  message(FATAL_ERROR "layering violations:\n  ${text}")
endif()
message(STATUS "layers: includes and links follow fixedpoint <- common <- stream, golden, host <- drivers")
