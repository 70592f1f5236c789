# Helpers that make every library, program, test and benchmark of the testbed the same way
# (STYLE.md, point 1). Includes start at the repository root: #include "common/geodesy/..."

get_filename_component(TESTBED_ROOT ${CMAKE_CURRENT_LIST_DIR}/.. ABSOLUTE)
# Frames captured from another ETSI stack: shared data beside the clone (as in CI), read by the
# tests in place rather than copied into the project.
set(TESTBED_INTEROP_DIR ${TESTBED_ROOT}/../shared/interop
    CACHE PATH "Folder of the captures from other ETSI stacks (shared/interop)")
# The OpenDRIVE test maps (shared/data/opendrive), read in place by tests and benchmarks; tests
# get it as TESTBED_OPENDRIVE_DIR (a git worktree lies elsewhere than a clone).
set(TESTBED_OPENDRIVE_DIR ${TESTBED_ROOT}/../shared/data/opendrive
    CACHE PATH "Folder of the shared OpenDRIVE test maps (shared/data/opendrive)")

add_library(testbed_options INTERFACE)
add_custom_target(fuzzers)  # `cmake --build DIR --target fuzzers` builds every fuzz target
target_compile_options(testbed_options INTERFACE -Wall -Wextra -Wpedantic)
if(TESTBED_WERROR)
  target_compile_options(testbed_options INTERFACE -Werror)
endif()
if(TESTBED_SANITIZE)
  set(_san -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_compile_options(testbed_options INTERFACE ${_san})
  target_link_options(testbed_options INTERFACE ${_san})
endif()
if(TESTBED_FUZZ)
  # Coverage feedback from every library a fuzz target reaches, not only from its own file: all
  # the testbed's code (every target of these helpers takes testbed_options) gets libFuzzer's
  # counters, and whatever links it the coverage runtime; fuzz targets add -fsanitize=fuzzer.
  # Prebuilt Debian libraries are not rebuilt and stay as they are.
  target_compile_options(testbed_options INTERFACE -fsanitize=fuzzer-no-link)
  target_link_options(testbed_options INTERFACE -fsanitize=fuzzer-no-link)
endif()

# testbed_library(<name> SOURCES ... [DEPS ...] [PRIVATE_DEPS ...])
# Makes target <name> with alias testbed::<name>; header-only when SOURCES is empty.
function(testbed_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  if(ARG_SOURCES)
    add_library(${name} STATIC ${ARG_SOURCES})
    target_include_directories(${name} PUBLIC ${TESTBED_ROOT})
    target_link_libraries(${name} PUBLIC testbed_options ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  else()
    add_library(${name} INTERFACE)
    target_include_directories(${name} INTERFACE ${TESTBED_ROOT})
    target_link_libraries(${name} INTERFACE testbed_options ${ARG_DEPS})
  endif()
  add_library(testbed::${name} ALIAS ${name})
endfunction()

# testbed_program(<name> SOURCES ... [DEPS ...])
function(testbed_program name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_include_directories(${name} PRIVATE ${TESTBED_ROOT})
  target_link_libraries(${name} PRIVATE testbed_options ${ARG_DEPS})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bin)
endfunction()

# testbed_gtest(<name> SOURCES ... [DEPS ...] [LABELS ...] [TIMEOUT s])
# One line per test binary; every test in it is registered with ctest (label "unit" unless
# given), so that `ctest -L unit` runs the fast ones.
function(testbed_gtest name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_include_directories(${name} PRIVATE ${TESTBED_ROOT})
  target_link_libraries(${name} PRIVATE testbed_options ${ARG_DEPS} GTest::gtest GTest::gmock
                                        GTest::gtest_main)
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  include(GoogleTest)
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${TESTBED_ROOT}
    PROPERTIES LABELS "${ARG_LABELS}" TIMEOUT ${ARG_TIMEOUT}
               ENVIRONMENT "TESTBED_BIN=${CMAKE_BINARY_DIR}/bin;TESTBED_ROOT=${TESTBED_ROOT};TESTBED_OPENDRIVE_DIR=${TESTBED_OPENDRIVE_DIR}"
    DISCOVERY_TIMEOUT 60)
endfunction()

# testbed_benchmark(<name> SOURCES ... [DEPS ...]) — Google Benchmark program in bin/bench/.
function(testbed_benchmark name)
  if(NOT TESTBED_BENCHMARKS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_include_directories(${name} PRIVATE ${TESTBED_ROOT})
  target_link_libraries(${name} PRIVATE testbed_options ${ARG_DEPS} benchmark::benchmark)
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bench)
endfunction()

# testbed_fuzzer(<name> SOURCES ... [DEPS ...] CORPUS dir... MIN_COVERAGE edges [DICT file]
#                [SECONDS s])
# A libFuzzer target, built only with TESTBED_FUZZ (clang); registered with ctest under label
# "fuzz" twice: fuzz.<name> runs it for a bounded time on its corpus folders (new inputs go to
# the build's <name>.corpus, the folders are only read), and fuzz.<name>.coverage runs the
# corpus once and fails when fewer than MIN_COVERAGE edges are covered — the floor that says
# the code under test is instrumented and reached (cmake/FuzzCoverage.cmake). Set it about 15 %
# under what the corpus covers in the fuzz build of scripts/test, so that a lost library's
# counters fail it (README, "Fuzzing"). SECONDS defaults to 20: with 18 targets on two cores
# that is three minutes of CI; longer campaigns run by hand (README, "Fuzzing").
function(testbed_fuzzer name)
  cmake_parse_arguments(ARG "" "SECONDS;MIN_COVERAGE;DICT" "SOURCES;DEPS;CORPUS" ${ARGN})
  if(NOT ARG_CORPUS OR NOT ARG_MIN_COVERAGE MATCHES "^[1-9][0-9]*$")
    message(FATAL_ERROR "testbed_fuzzer(${name}): needs CORPUS and MIN_COVERAGE (edges > 0)")
  endif()
  if(NOT TESTBED_FUZZ)
    return()
  endif()
  if(NOT ARG_SECONDS)
    set(ARG_SECONDS 20)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  add_dependencies(fuzzers ${name})
  target_include_directories(${name} PRIVATE ${TESTBED_ROOT})
  target_compile_options(${name} PRIVATE -fsanitize=fuzzer)
  target_link_options(${name} PRIVATE -fsanitize=fuzzer)
  target_link_libraries(${name} PRIVATE testbed_options ${ARG_DEPS})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/fuzz)
  set(work ${CMAKE_BINARY_DIR}/fuzz/${name}.corpus)
  set(dirs "")
  foreach(dir IN LISTS ARG_CORPUS)
    string(APPEND dirs " '${dir}'")
  endforeach()
  set(dict "")
  if(ARG_DICT)
    set(dict "-dict='${ARG_DICT}'")
  endif()
  add_test(NAME fuzz.${name}
           COMMAND ${CMAKE_COMMAND} -E env ASAN_OPTIONS=detect_leaks=1
                   sh -c "mkdir -p '${work}' && exec '$<TARGET_FILE:${name}>' -max_total_time=${ARG_SECONDS} -timeout=5 -rss_limit_mb=2048 ${dict} '${work}'${dirs}")
  math(EXPR limit "${ARG_SECONDS} * 3 + 60")
  set_tests_properties(fuzz.${name} PROPERTIES LABELS fuzz TIMEOUT ${limit})
  add_test(NAME fuzz.${name}.coverage
           COMMAND ${CMAKE_COMMAND} -DFUZZER=$<TARGET_FILE:${name}>
                   -DMIN_COVERAGE=${ARG_MIN_COVERAGE} "-DCORPUS=${ARG_CORPUS}"
                   -P ${TESTBED_ROOT}/cmake/FuzzCoverage.cmake)
  set_tests_properties(fuzz.${name}.coverage PROPERTIES LABELS fuzz TIMEOUT 120)
endfunction()
