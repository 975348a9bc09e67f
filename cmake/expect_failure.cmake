# cmake -DCOMMAND="prog;arg;..." -DEXPECT=<regex> [-DNO_OUTPUT=<path>] -P expect_failure.cmake
# Runs COMMAND and passes only if it exits non-zero AND its output (stdout and
# stderr) matches EXPECT: a test of an error path asserts which error it got.
# With NO_OUTPUT, the failed run must also have left nothing at that path.
if(NOT DEFINED COMMAND OR NOT DEFINED EXPECT)
  message(FATAL_ERROR "expect_failure.cmake: COMMAND and EXPECT are required")
endif()
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
if(rc EQUAL 0)
  message(FATAL_ERROR "expected a failure, got exit 0; output:\n${all}")
endif()
if(NOT all MATCHES "${EXPECT}")
  message(FATAL_ERROR "exit ${rc}, but the output does not match '${EXPECT}':\n${all}")
endif()
if(DEFINED NO_OUTPUT AND EXISTS "${NO_OUTPUT}")
  message(FATAL_ERROR "failed as expected, but left output at ${NO_OUTPUT}")
endif()
message(STATUS "failed as expected (exit ${rc}): ${all}")
