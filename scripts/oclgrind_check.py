#!/usr/bin/env python3
"""Every swarmcl kernel under Oclgrind (issue 27; docs/reliability.md, "Oclgrind").

Runs a fixed list of small GoogleTest cases, one test per process, two at a
time, under `oclgrind --data-races --uninitialized`, mostly in the GPU
profile (one agent per work-item, gpu_local_size(): what a GPU runs)
and a few in the CPU profile and at explicit widths (ScopedKernelWidth) for
the 8/16-lane kernels.  Fails on any Oclgrind report (an out-of-bounds
access, a data race, a use of uninitialised memory), on a test that fails or
crashes under Oclgrind, and on a kernel of kernels/ that no case ran
(Oclgrind's --inst-counts names every kernel it executed): every kernel runs.
No report is suppressed.  136-147 s on 2 cores shared with other jobs
(2026-11-27); 581 s on the 2-core AMD EPYC without AVX-512 (2026-11-29)
before the three longest cases were made small (docs/reliability.md).  What it
found in swarmcl: force_model_repulsion_w read the never-written pads of the
fine grid's copy of the positions (now zeroed when allocated).

Oclgrind 21.10 (Debian) has bugs of its own that gave false reports or
wrong values; each is worked around where it arises, on Oclgrind only or
with the same values everywhere, never by hiding a report:
- Its shadow memory is kept per buffer id: a host write, fill or copy into a
  buffer replaces the buffer's whole shadow by one the size of that write
  (the rest of the buffer then reads as uninitialised and later kernel
  stores there are dropped), and a released buffer's shadow stays for the
  next buffer given its id (Uninitialized::hostMemoryStore ->
  ShadowMemory::allocate; no memoryDeallocated).  The library therefore
  keeps every buffer until its context goes when it runs on Oclgrind, and
  turns any host write, fill or copy but a whole-buffer write into a kernel
  copy (Context::on_oclgrind(), host/device/buffer.hpp): every case may make
  several swarms, and a report means a kernel read bytes no one wrote.
- Its shufflevector rule compares mask elements with
  llvm::Value::UndefValueVal (11 in LLVM 14) instead of -1: the lane a
  swizzle takes from element 11 reads as uninitialised, and an undefined
  mask element reads a shadow 4 GiB away (junk for a float3's fourth lane;
  a crash in noise_load_xyz_w's 16-lane vector literal).  The check
  builds with -DSWCL_OCLGRIND: the 16-lane reductions take their halves
  through private memory (kernels/lib/halves.cl) and the noise module's
  16-lane loads go lane by lane (lib/noise_field.cl), the same values.
- Its integer min/max/clamp builtins read a scalar argument as a vector:
  min(ugentype, uint) gives garbage lanes (no report, wrong values:
  policy_observe_w's lanes saw themselves).  SWCL_BLAST
  (kernels/wide/width.inc.cl) passes the bound as a vector, on every device.
- -cl-opt-disable: with clang's optimiser Oclgrind stops at intrinsics it
  does not implement ("Undefined external function: llvm.usub.sat.i32" in
  grid_merge).  -DSWCL_NO_ALWAYS_INLINE: LLVM 14's always-inliner leaves
  llvm.experimental.noalias.scope.decl calls even then (helpers taking or
  returning structs), which Oclgrind does not implement either; the define
  drops the kernels' always_inline attributes, nothing else.

Exit 77 (ctest's SKIP_RETURN_CODE) when oclgrind is not installed.
"""
import argparse
import concurrent.futures
import glob
import os
import re
import shutil
import subprocess
import sys
import time

GPU = {"SWARMCL_DEVICE_PROFILE": "gpu"}
CPU = {"SWARMCL_DEVICE_PROFILE": "cpu"}

# (binary, gtest filter, environment).  Small sizes: a few to a few hundred
# agents, grids of 8 to 20 cells a side; the tests marked "small" exist for
# this check (the full-size ones take minutes each under Oclgrind).
CASES = [
    # The neighbour grid, the point grid, the swarm's state and queries.
    ("test_grid", "Grid.RandomPointsMatchHostCountingSort", GPU),
    ("test_grid", "Grid.CountingAndChunkedSortsBuildTheSameGrid", GPU),
    ("test_grid", "Grid.EmptyAndSingleAgentSwarms", GPU),
    ("test_grid", "Grid.ReorderKeepsEachAgentsVelocityWithIt", GPU),
    ("test_grid", "Grid.AgentsOutsideTheDomainAreClampedIntoBorderCells", GPU),
    ("test_grid", "Grid.AllAgentsInOneCellAndDuplicates", GPU),
    ("test_grid", "Grid.PermuteStateMovesEveryArrayByThePermutation", CPU),
    # The CPU profile's bucket sort, and its compaction and merge with movers
    # and stayers mixed (their branch-free loops).
    ("test_grid", "Grid.MovedAgentsMatchHostCountingSort", CPU),
    ("test_point_grid", "PointGrid.NoPointsAndOnePoint", GPU),
    ("test_point_grid", "PointGrid.GivenGeometryMatchesBruteForce", GPU),
    ("test_point_grid", "PointGrid.GroupsApartHaveTheGeometryAndOrderOfEachGroupAlone", GPU),
    ("test_neighbors", "Neighbors.LatticeAtExactlyTheRadius", GPU),
    ("test_neighbors", "Neighbors.SparseSwarmNearestSearchesFar", GPU),  # three swarms in one process
    # The CPU profile's count SWCL_W slots a work-item (neighbor_count_w).
    ("test_neighbors", "Neighbors.LatticeAtExactlyTheRadius", CPU),
    ("test_capi", "CApi.StepMovesBallisticallyAndCounts", GPU),  # no model: integrate_ballistic
    ("test_capi", "CApi.GrowingAndShrinkingTheAgentCountKeepsVelocities", GPU),  # set_count's fill
    ("test_step_stages", "StepStages.ModelWithoutMinDistanceCountsStepsOnly", GPU),
    # The field model, minimum distance enforcement, the noise module.
    ("test_field_model", "FieldModelReference.TimeVaryingCurlNoiseAndGoalOneStep", GPU),
    ("test_field_model", "FieldModelReference.WhiteNoiseAndGoalOneStep", GPU),
    ("test_field_model", "FieldModelTest.MinimumDistanceSeparatesIsolatedPairsExactly", GPU),
    ("test_field_model", "FieldModelTest.MinimumDistanceSeparatesIsolatedPairsExactly", CPU),
    ("test_noise", "BakedNoise.SmallBakeIsTheProceduralFieldAtNodesAndItsInterpolationBetween", GPU),
    ("test_noise", "BakedNoise.SmallBakeIsTheProceduralFieldAtNodesAndItsInterpolationBetween", CPU),
    # Worlds: the -DSWCL_WORLDS kernels (grid keys, MDE, queries, field model).
    ("test_worlds", "Worlds.SmallWorldsAreBitwiseTheSwarmsAlone", GPU),
    ("test_worlds", "Worlds.SmallWorldsAreBitwiseTheSwarmsAlone", CPU),
    ("test_worlds", "Worlds.SmallStepFramesAreTheFramesOfStepThenRead", GPU),  # frame_xyz
    # Worlds' metrics: the point grid's groups, per-world atomic histograms
    # and blocks of moments (the GPU profile only: each world's histograms
    # take Oclgrind ~15 s to clear and read; the CPU profile's chunk copies
    # are one work-item each, and their ranges are checked by the bitwise
    # comparison in every ctest run).
    ("test_worlds", "Worlds.SmallWorldsMetricsAreBitwiseThoseOfTheSwarmAlone", GPU),
    # The force model: its terms, the 16-lane kernels and MDE, mesh obstacles
    # (their signed distance, push-out and sampled distance).
    ("test_force_model", "ForceTerms.InteractionZonesMatchBruteForce", GPU),
    ("test_force_model", "ForceModel.SmallMinDistanceMatchesItsReference", GPU),
    ("test_force_model", "ForceModel.SmallWideKernelMatchesTheScalarOne", CPU),
    # The force model's world kernels (-DSWCL_WORLDS): offsets, the fine
    # grid per world (point_grid groups apart), MDE per world.
    ("test_force_worlds", "ForceWorlds.SmallWorldsAreBitwiseTheSwarmsAlone", GPU),
    ("test_force_worlds", "ForceWorlds.SmallWorldsAreBitwiseTheSwarmsAlone", CPU),
    ("test_force_worlds", "ForceWorlds.SmallWorldsWithObstaclesAreBitwiseTheSwarmsAlone", GPU),
    ("test_force_obstacles", "ForceMeshObstacles.InsectsJustInsideABoxMeshAreOutsideAfterTheNextStep", GPU),
    # The path model (signed distance, baked and rebaked noise, both widths).
    # Its world kernels: offsets, per-world direction fields, MDE per world.
    ("test_path_worlds", "PathWorlds.SmallWorldsAreBitwiseTheSwarmsAlone", GPU),
    ("test_path_chasing", "PathChasing.SmallGridsMovingTheTargetMatchesAFreshBuildAtWidths1And16", GPU),
    # The energy model.
    ("test_energy_model", "EnergyModel.EveryTermMatchesTheHostReference", GPU),
    ("test_energy_model", "EnergyModel.EveryTermMatchesTheHostReference", CPU),
    # The policy model and the RL environment.
    ("test_policy", "PolicyStep.SmallNetAppliesTheActionsWithEquationTwoAtWidths1And16", GPU),
    # The GPU profile's tiled MLP (local memory, barriers; partial tiles).
    ("test_policy", "PolicyMlp.SmallTiledKernelGivesPolicyMlpsBits", GPU),
    ("test_rl_env", "RlEnv.SmallRagMatchesReference", GPU),
    # The evaluation metrics (the CPU profile's histogram kernel too).
    ("test_swarm_metrics", "SwarmMetrics.NonFinitePositionsAreCountedAndRefuseAPdf", GPU),
    ("test_swarm_metrics", "SwarmMetrics.NonFinitePositionsAreCountedAndRefuseAPdf", CPU),
    ("test_swarm_metrics", "SwarmMetrics.NearestNeighbourMatchesBruteForce", GPU),
    # The CPU profile's 16-lane kernels (metrics_nearest_w, metrics_sample_w).
    ("test_swarm_metrics", "SwarmMetrics.NearestNeighbourMatchesBruteForce", CPU),
    # metrics_nearest_w with a box a row of cells each (MN_ROWS_APART), 8 lanes.
    ("test_swarm_metrics", "SwarmMetrics.NearestNeighbourMatchesBruteForceWithTheRowsApart", CPU),
]

# Larger cases, not run under Oclgrind (minutes each there), that build
# programs natively with other defines: scripts/nvptx_check.py --census runs
# them too, so every GPU-profile program is compiled for NVIDIA.
CENSUS_EXTRA = [
    ("test_neighbors", "Neighbors.CrowdedCellWithDuplicatesAndTies", GPU),
    ("test_noise", "BakedNoise.AgreesWithProceduralAtNodesAndWithinTrilinearErrorBetween", GPU),
    ("test_sdf", "Sdf.MeshWithAHole", GPU),
    ("test_path_field", "PathModel.GlobalVelocityMatchesTheHostReference", GPU),
    ("test_path_field", "PathModel.BakedMeshNoiseMatchesProcedural", GPU),
    ("test_path_chasing", "PathChasing.MovingTheTargetMatchesAFreshBuild", GPU),
    ("test_force_obstacles", "ForceMeshObstacles.SampledDistanceOfASphereMeshIsWithinACell", GPU),
    ("test_policy", "PolicyObserve.GridObservationsEqualTheAllPairsReference", GPU),
    ("test_policy", "PolicyMlp.KernelMatchesReference", GPU),
    ("test_policy", "PolicyStep.AppliesTheActionsWithEquationTwo", GPU),
    ("test_rl_env", "RlEnv.ObservationsAndRewardsMatchReference", GPU),
]

# Seconds each case took under Oclgrind (2 at a time on 2 cores shared with
# other jobs): only to start the longest first.
EXPECTED_SECONDS = {
    # The first three: 2026-11-29, 2-core AMD EPYC without AVX-512, two at a time.
    "test_force_worlds.ForceWorlds.SmallWorldsWithObstaclesAreBitwiseTheSwarmsAlone": 49,
    "test_force_worlds.ForceWorlds.SmallWorldsAreBitwiseTheSwarmsAlone": 40,
    "test_path_worlds.PathWorlds.SmallWorldsAreBitwiseTheSwarmsAlone": 25,
    "test_worlds.Worlds.SmallWorldsAreBitwiseTheSwarmsAlone": 20,
    "test_force_model.ForceModel.SmallWideKernelMatchesTheScalarOne": 40,
    "test_force_model.ForceModel.SmallMinDistanceMatchesItsReference": 10,
    "test_path_chasing.PathChasing.SmallGridsMovingTheTargetMatchesAFreshBuildAtWidths1And16": 49,
    "test_rl_env.RlEnv.SmallRagMatchesReference": 10,
    "test_energy_model.EnergyModel.EveryTermMatchesTheHostReference": 28,
    "test_swarm_metrics.SwarmMetrics.NearestNeighbourMatchesBruteForce": 19,
    "test_worlds.Worlds.SmallWorldsMetricsAreBitwiseThoseOfTheSwarmAlone": 44,
    "test_force_model.ForceTerms.InteractionZonesMatchBruteForce": 18,
    "test_grid.Grid.RandomPointsMatchHostCountingSort": 14,
    "test_force_obstacles.ForceMeshObstacles.InsectsJustInsideABoxMeshAreOutsideAfterTheNextStep": 13,
}

REPORT = re.compile(r"^(Uninitialized value|Controlflow depends on uninitialized|Instruction depends on an uninitialized|"
                    r"Invalid (read|write)|OCLGRIND FATAL ERROR|"
                    r"(Read-write|Write-write) data race|Work-group divergence|Barrier divergence|"
                    r"Undefined external function|Uninitialized address|.*data race|Oclgrind - )", re.M)
KERNEL_RAN = re.compile(r"Instructions executed for kernel '(\w+)'")


def source_kernels(kernel_dir):
    names = set()
    for path in glob.glob(os.path.join(kernel_dir, "**", "*.cl"), recursive=True):
        text = re.sub(r"//[^\n]*", "", open(path, encoding="utf-8").read())
        names.update(m.group(1) for m in re.finditer(r"__kernel\s+void\s+(?!SWCL_KERNEL\b)([A-Za-z_]\w*)", text))
        for m in re.finditer(r"\bvoid\s+SWCL_KERNEL\((\w+)\)", text):
            names.update({m.group(1), m.group(1) + "_w"})
    return names


def list_tests(binary, gfilter):
    out = subprocess.run([binary, "--gtest_list_tests", f"--gtest_filter={gfilter or '*'}"],
                         capture_output=True, text=True, timeout=60).stdout
    tests, suite = [], None
    for line in out.splitlines():
        if not line.strip() or line.startswith("Running main"):
            continue
        if not line.startswith(" "):
            suite = line.split()[0]
        else:
            tests.append(suite + line.split()[0])
    return tests


def run_case(oclgrind, binary, test, env, timeout, log_dir):
    e = dict(os.environ)
    e.update(env)
    tag = f"{os.path.basename(binary)}.{test}.{env['SWARMCL_DEVICE_PROFILE']}".replace("/", "_")
    cmd = [oclgrind, "--data-races", "--uninitialized", "--inst-counts", "--build-options",
           "-cl-opt-disable -DSWCL_NO_ALWAYS_INLINE -DSWCL_OCLGRIND",
           "--max-errors", "20", binary, f"--gtest_filter={test}"]
    t0 = time.time()
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, env=e, timeout=timeout)
        out, rc = r.stdout + r.stderr, r.returncode
    except subprocess.TimeoutExpired as x:
        out = (x.stdout or b"").decode(errors="replace") if isinstance(x.stdout, bytes) else (x.stdout or "")
        rc = "timeout"
    dt = time.time() - t0
    with open(os.path.join(log_dir, tag + ".log"), "w") as f:
        f.write(out)
    reports = [m.group(0) for m in REPORT.finditer(out)]
    ran = set(KERNEL_RAN.findall(out))
    passed = rc == 0 and "[  PASSED  ] 1 test" in out
    return tag, rc, passed, reports, ran, dt, out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", required=True, help="the build folder (tests/ under it)")
    ap.add_argument("--kernels", required=True, help="the kernels/ source folder")
    ap.add_argument("--jobs", type=int, default=max(1, min(2, os.cpu_count() or 1)))
    ap.add_argument("--timeout", type=int, default=600, help="seconds per case (2-core machines differ by 2-3x "
                    "under Oclgrind)")
    ap.add_argument("--log-dir", default=None, help="per-case logs (default: <build>/oclgrind)")
    ap.add_argument("--only", default=None, help="regex: run only the cases whose tag matches (no coverage check)")
    args = ap.parse_args()

    oclgrind = shutil.which("oclgrind")
    if not oclgrind:
        print("oclgrind check SKIPPED: oclgrind is not installed (Debian: apt-get install oclgrind; "
              "scripts/bootstrap.sh installs it)")
        return 77
    log_dir = args.log_dir or os.path.join(args.build, "oclgrind")
    os.makedirs(log_dir, exist_ok=True)

    jobs = []
    for binary, gfilter, env in CASES:
        path = os.path.join(args.build, "tests", binary)
        if not os.access(path, os.X_OK):
            print(f"oclgrind check FAILED: {path} is not built")
            return 1
        tests = list_tests(path, gfilter)
        if not tests:
            print(f"oclgrind check FAILED: no test matches {binary} --gtest_filter={gfilter}")
            return 1
        for t in tests:
            tag = f"{binary}.{t}.{env['SWARMCL_DEVICE_PROFILE']}"
            if args.only and not re.search(args.only, tag):
                continue
            jobs.append((path, t, env))

    # Longest first, so the two workers finish close together.
    jobs.sort(key=lambda j: -EXPECTED_SECONDS.get(os.path.basename(j[0]) + "." + j[1], 5))
    t_start = time.time()
    failures, ran_all = [], set()
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futs = [pool.submit(run_case, oclgrind, p, t, env, args.timeout, log_dir) for p, t, env in jobs]
        for fut in concurrent.futures.as_completed(futs):
            tag, rc, passed, reports, ran, dt, out = fut.result()
            ran_all |= ran
            status = "clean" if passed and not reports else "FAILED"
            print(f"  {status:6s} {dt:6.1f} s  {tag}  ({len(ran)} kernels, {len(reports)} reports)", flush=True)
            if reports:
                first = out[out.find(reports[0]):][:600]
                failures.append(f"{tag}: {len(reports)} Oclgrind reports; the first:\n{first}")
            elif not passed:
                tail = "\n".join(out.strip().splitlines()[-8:])
                failures.append(f"{tag}: the test failed or crashed under Oclgrind (status {rc}):\n{tail}")

    kernels = source_kernels(args.kernels)
    if not args.only:
        missing = sorted(kernels - ran_all)
        if missing:
            failures.append("kernels no case ran: " + ", ".join(missing))
    print(f"oclgrind check: {len(jobs)} cases, {len(kernels & ran_all)} of the {len(kernels)} kernels of kernels/ "
          f"ran, {time.time() - t_start:.0f} s ({args.jobs} at a time); logs in {log_dir}")
    if failures:
        print("oclgrind check FAILED:")
        for f in failures:
            print("  " + f.replace("\n", "\n    "))
        return 1
    print("oclgrind check passed: no report from --data-races --uninitialized" +
          ("" if args.only else "; every kernel ran"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
