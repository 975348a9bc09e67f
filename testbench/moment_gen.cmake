# Co-simulation of rtl_model/moment_gen.sv against stream::MomentGen.
ceilnav_add_cosim(cosim_moment_gen_test TOP moment_gen SV moment_gen.sv
                  SOURCES ${CMAKE_CURRENT_LIST_DIR}/cosim_moment_gen_test.cpp LIBS ${OpenCV_LIBS})
# Our test source gets the project warnings as errors (the Verilated sources
# in the same target do not).
set_source_files_properties(
  ${CMAKE_CURRENT_LIST_DIR}/cosim_moment_gen_test.cpp
  PROPERTIES COMPILE_OPTIONS "-Wall;-Wextra;-Wpedantic;-Wshadow;-Wconversion;-Wsign-conversion;-Werror")
