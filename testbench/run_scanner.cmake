# Co-simulation of rtl_model/run_scanner.sv against stream::RunScanner, at the
# default FifoDepth (1024) and at FifoDepth = 8 (second model, prefix
# Vrun_scanner_d8) so that overflow and lost trailers are exercised.
ceilnav_add_cosim(cosim_run_scanner_test TOP run_scanner SV run_fifo.sv run_scanner.sv
                  SOURCES ${CMAKE_CURRENT_LIST_DIR}/cosim_run_scanner_test.cpp LIBS ${OpenCV_LIBS})
verilate(cosim_run_scanner_test SOURCES ${CEILNAV_GENERATED_DIR}/ceilnav_widths_pkg.sv ${CEILNAV_RTL_DIR}/ceilnav_pkg.sv
         ${CEILNAV_RTL_DIR}/run_fifo.sv ${CEILNAV_RTL_DIR}/run_scanner.sv
         TOP_MODULE run_scanner PREFIX Vrun_scanner_d8 ${CEILNAV_VERILATOR_COVERAGE}
         VERILATOR_ARGS -Wno-fatal --assert -O3 --x-assign unique --x-initial unique -GFifoDepth=8
         TRACE_FST)
# Our test source gets the project warnings as errors (the Verilated sources
# in the same target do not).
set_source_files_properties(
  ${CMAKE_CURRENT_LIST_DIR}/cosim_run_scanner_test.cpp
  PROPERTIES COMPILE_OPTIONS "-Wall;-Wextra;-Wpedantic;-Wshadow;-Wconversion;-Wsign-conversion;-Werror")
