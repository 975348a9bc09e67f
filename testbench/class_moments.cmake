# Co-simulation of rtl_model/class_moments.sv against stream::ClassMoments.
ceilnav_add_cosim(cosim_class_moments_test TOP class_moments SV class_moments.sv
                  SOURCES ${CMAKE_CURRENT_LIST_DIR}/cosim_class_moments_test.cpp LIBS ${OpenCV_LIBS})
# Our test source gets the project warnings as errors (the Verilated sources
# in the same target do not).
set_source_files_properties(
  ${CMAKE_CURRENT_LIST_DIR}/cosim_class_moments_test.cpp
  PROPERTIES COMPILE_OPTIONS "-Wall;-Wextra;-Wpedantic;-Wshadow;-Wconversion;-Wsign-conversion;-Werror")
