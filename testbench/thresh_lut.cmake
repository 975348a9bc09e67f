# thresh_lut: RTL (rtl_model/thresh_lut.sv) == C++ (stream/thresh_lut.cpp).
ceilnav_add_cosim(cosim_thresh_lut_test TOP thresh_lut SV thresh_lut.sv
                  SOURCES ${CMAKE_CURRENT_LIST_DIR}/cosim_thresh_lut_test.cpp
                  LIBS ceilnav_golden)
# Our own test code is held to the project's warnings (the Verilated code is not).
get_target_property(ceilnav_cosim_warnings ceilnav_warnings INTERFACE_COMPILE_OPTIONS)
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/cosim_thresh_lut_test.cpp
                            PROPERTIES COMPILE_OPTIONS "${ceilnav_cosim_warnings}")
