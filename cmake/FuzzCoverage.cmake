# cmake -DFUZZER=path -DMIN_COVERAGE=edges -DCORPUS=dir[;dir...] -P FuzzCoverage.cmake
#
# The coverage floor of a fuzz target (testbed_fuzzer's fuzz.<name>.coverage test): runs the
# target once over its corpus folders (-runs=0: the seeds only, nothing written) and reads what
# libFuzzer says, "INFO: Loaded 1 modules (M inline 8-bit counters)" and "INITED cov: E ft: F".
# Fails unless E reaches MIN_COVERAGE. A target whose libraries are built without libFuzzer's
# instrumentation has counters for its own file only and covers a fraction of its floor.

foreach(var FUZZER MIN_COVERAGE CORPUS)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "FuzzCoverage.cmake: ${var} not given")
  endif()
endforeach()

execute_process(COMMAND ${FUZZER} -runs=0 ${CORPUS}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${FUZZER} -runs=0 failed (${rc}):\n${out}")
endif()
if(NOT out MATCHES "INFO: Loaded ([0-9]+) modules +\\(([0-9]+) inline 8-bit counters\\)")
  message(FATAL_ERROR "${FUZZER}: no inline 8-bit counters reported (not built with "
                      "-fsanitize=fuzzer?):\n${out}")
endif()
set(modules ${CMAKE_MATCH_1})
set(counters ${CMAKE_MATCH_2})
if(NOT out MATCHES "INITED cov: ([0-9]+) ft: ([0-9]+)")
  message(FATAL_ERROR "${FUZZER}: no INITED line:\n${out}")
endif()
set(cov ${CMAKE_MATCH_1})
set(ft ${CMAKE_MATCH_2})
get_filename_component(name ${FUZZER} NAME)
string(CONCAT figures "${name}: ${counters} counters in ${modules} module(s), the corpus covers "
                      "${cov} edges (ft ${ft}), floor ${MIN_COVERAGE} edges")
if(cov LESS MIN_COVERAGE)
  message(FATAL_ERROR "${figures}: below the floor. Is the code under test built with "
                      "-fsanitize=fuzzer-no-link, and does the corpus reach it?")
endif()
message(STATUS "${figures}")
