# cmake -P bench/fuzz/list_targets.cmake: one line per fuzz target,
# "<name> <seed folder>...", for run.sh.
include(${CMAKE_CURRENT_LIST_DIR}/targets.cmake)
foreach(t ${SWARMCL_FUZZ_TARGETS})
  string(REPLACE ";" " " seeds "${SWARMCL_FUZZ_SEEDS_${t}}")
  execute_process(COMMAND ${CMAKE_COMMAND} -E echo "${t} ${seeds}")
endforeach()
