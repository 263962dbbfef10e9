# Runs fleetnav-plan-bench with a tiny budget and checks that the log has the structure of
# OMPL's benchmark log (ompl::tools::Benchmark::saveResultsToStream, OMPL 1.5): the header
# lines, "<n> planners", then per planner its name, "<n> common properties",
# "<n> properties for each run", "<n> runs", one ';'-separated line per run and a "." line.
# Usage: cmake -DBENCH=<binary> -DOUT=<log file> -P check_plan_bench_log.cmake
set(planners lattice-lely lattice-omni lattice-ackermann ompl-omni ompl-reeds-shepp)
set(runs 2)
file(REMOVE ${OUT})
execute_process(
  COMMAND ${BENCH} --runs ${runs} --time-limit-s 2 --log-out ${OUT} --json
  RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fleetnav-plan-bench exited with ${rc}: ${stderr}")
endif()
if(NOT EXISTS ${OUT})
  message(FATAL_ERROR "no log written to ${OUT}")
endif()
file(READ ${OUT} log)
# CMake lists split on ';': count the run lines' separators as ','.
string(REPLACE ";" "," log "${log}")

function(expect_count regex count what)
  string(REGEX MATCHALL "${regex}" hits "${log}")
  list(LENGTH hits n)
  if(NOT n EQUAL count)
    message(FATAL_ERROR "${what}: expected ${count} matches of '${regex}', found ${n}")
  endif()
endfunction()

list(LENGTH planners n_planners)
math(EXPR n_run_lines "${n_planners} * ${runs}")
expect_count("\nExperiment [^\n]+\n" 1 "experiment name")
expect_count("\n[0-9]+ is the random seed\n" 1 "random seed")
expect_count("\n[0-9.]+ seconds per run\n" 1 "time per run")
expect_count("\n[0-9.]+ MB per run\n" 1 "memory per run")
expect_count("\n${runs} runs per planner\n" 1 "runs per planner")
expect_count("\n[0-9]+ enum types?\n" 1 "enum types")
expect_count("\n${n_planners} planners\n" 1 "planner count")
expect_count("\n[0-9]+ common properties\n" ${n_planners} "common properties per planner")
expect_count("\n[0-9]+ properties for each run\n" ${n_planners} "run properties per planner")
expect_count("\n${runs} runs\n" ${n_planners} "run count per planner")
expect_count("\n\\.\n" ${n_planners} "planner terminators")
expect_count("[^\n]*, \n" ${n_run_lines} "run lines")
foreach(p ${planners})
  # The planner's name opens its block and is followed by its common properties.
  expect_count("\ngeometric_${p}\n[0-9]+ common properties\n" 1 "block of ${p}")
  if(NOT stdout MATCHES "\"name\":\"geometric_${p}\"")
    message(FATAL_ERROR "JSON summary lacks ${p}: ${stdout}")
  endif()
endforeach()
foreach(prop "time REAL" "solved BOOLEAN" "exact BOOLEAN" "path length_m REAL")
  expect_count("\n${prop}\n" ${n_planners} "run property '${prop}'")
endforeach()
foreach(key solved_rate median_time_ms median_length_m)
  if(NOT stdout MATCHES "\"${key}\":")
    message(FATAL_ERROR "JSON summary lacks ${key}: ${stdout}")
  endif()
endforeach()
message(STATUS "OMPL benchmark log structure ok: ${OUT}")
