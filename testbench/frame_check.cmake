# frame_check: RTL (rtl_model/frame_check.sv) == C++ (stream/frame_check.cpp).
ceilnav_add_cosim(cosim_frame_check_test TOP frame_check SV frame_check.sv
                  SOURCES ${CMAKE_CURRENT_LIST_DIR}/cosim_frame_check_test.cpp
                  LIBS ceilnav_golden)
# Our own test code is held to the project's warnings (the Verilated code is not).
get_target_property(ceilnav_cosim_warnings ceilnav_warnings INTERFACE_COMPILE_OPTIONS)
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/cosim_frame_check_test.cpp
                            PROPERTIES COMPILE_OPTIONS "${ceilnav_cosim_warnings}")
