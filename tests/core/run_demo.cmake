# Runs mtc-interaction-demo and checks that it succeeds and plays the success
# run and every failure scenario of section 5.1 under both profiles.
# Usage: cmake -DDEMO=<path> -P run_demo.cmake
execute_process(COMMAND ${DEMO} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "demo exited with ${rc}: ${err}")
endif()
foreach(needle "=== Success" "=== Scenario 1 " "=== Scenario 2 " "=== Scenario 3 "
        "=== Scenario 4 " "=== Scenario 5 " "=== Scenario 6 " "=== Time limits"
        "[MTConnect 1.3]" "[MTConnect 1.6/1.8]" "FailAcknowledged" "Recovered"
        "CommsLost" "TimedOut" "final: cnc REQUEST READY, robot RESPONSE READY")
  string(FIND "${out}" "${needle}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "demo output does not mention '${needle}'")
  endif()
endforeach()
# Every scenario must end with both sides READY or NOT_READY.
string(REGEX MATCHALL "final: [^\n]*" finals "${out}")
foreach(line IN LISTS finals)
  if(line MATCHES "ACTIVE|FAIL|COMPLETE")
    message(FATAL_ERROR "a scenario did not recover: ${line}")
  endif()
endforeach()
list(LENGTH finals n)
if(n LESS 14)
  message(FATAL_ERROR "expected at least 14 scenario runs, saw ${n}")
endif()
