# The fuzz targets: one source bench/fuzz/fuzz_<name>.cpp each, defining
# LLVMFuzzerTestOneInput.  Adding a target: write that file and add its name
# here (the libFuzzer build, run.sh and the replay test all read this list).
set(SWARMCL_FUZZ_TARGETS
  obj            # OBJ obstacle meshes
  tracks_csv     # track CSV files
  scenario       # scenario JSON (model sections, energy spec, keyframes, meshes)
  dataset        # the reference dataset's binary file
  checkpoint     # swarm checkpoints: container + section decode
  run_checkpoint # the CLI's checkpoint.json and frames file
  policy_weights # trained actors (safetensors) of the policy model
)
# Seeds beyond bench/fuzz/corpus/<target>/: the project's example files
# (folders relative to the source root).
set(SWARMCL_FUZZ_SEEDS_obj examples/meshes)
set(SWARMCL_FUZZ_SEEDS_scenario examples/scenarios examples/evaluation)
set(SWARMCL_FUZZ_SEEDS_policy_weights models)

# Every fuzz executable (libFuzzer or replay) of `target` built from `sources`.
function(swarmcl_fuzz_executable exe target)
  add_executable(${exe} ${PROJECT_SOURCE_DIR}/bench/fuzz/fuzz_${target}.cpp ${ARGN})
  target_link_libraries(${exe} PRIVATE swarmcl_internal nlohmann_json::nlohmann_json)
  target_include_directories(${exe} PRIVATE ${PROJECT_SOURCE_DIR}/host ${PROJECT_SOURCE_DIR}/bench/fuzz)
  target_compile_definitions(${exe} PRIVATE
    SWARMCL_FUZZ_SCENARIO_DIR="${PROJECT_SOURCE_DIR}/examples/scenarios")
  if(target STREQUAL "run_checkpoint")
    target_sources(${exe} PRIVATE ${PROJECT_SOURCE_DIR}/cli/run_checkpoint.cpp)
  endif()
endfunction()
