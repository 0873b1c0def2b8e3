#!/usr/bin/env python3
"""Every swarmcl kernel under Oclgrind (issue 27; docs/reliability.md, "Oclgrind").

Runs a fixed list of small GoogleTest cases, one test per process, under
`oclgrind --data-races --uninitialized`, in the GPU profile (one agent per
work-item, the driver's local sizes: what a GPU runs) and a few in the CPU
profile for the explicit-width kernels.  Fails on any Oclgrind report (an
out-of-bounds access, a data race, a use of uninitialised memory), on a test
that fails or crashes under Oclgrind, and on a kernel of kernels/ that no case
ran (Oclgrind's --inst-counts names every kernel it executed).

Why one test per process: Oclgrind 21.10 reports reads of memory the same
work-item has just written once a process has released and re-created
buffers (first seen in radix_hist, whose work-item zeroes its histogram
column and then counts into it: a write-then-read in one work-item cannot
read uninitialised memory), so each case starts from a fresh Oclgrind.

Why -cl-opt-disable: Oclgrind 21.10 interprets LLVM 14 IR, and clang's
optimiser turns saturating and min/max idioms into intrinsics Oclgrind does
not implement ("Undefined external function: llvm.usub.sat.i32" in
grid_merge); without optimisation the IR keeps plain instructions.  Why
-DSWCL_NO_ALWAYS_INLINE: even then LLVM 14's always-inliner leaves
llvm.experimental.noalias.scope.decl calls (helpers taking or returning
structs), which Oclgrind 21.10 does not implement either ("When creating
kernel 'force_model_mde'": the force, energy and path models could not run);
the define drops the kernels' always_inline attributes, nothing else.

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

# (binary, gtest filter, environment).  Small sizes: each case is one test
# whose swarm is a few hundred to a few thousand agents.
CASES = [
    ("test_grid", "Grid.RandomPointsMatchHostCountingSort", GPU),
    ("test_grid", "Grid.EmptyAndSingleAgentSwarms", GPU),
    ("test_grid", "Grid.ReorderKeepsEachAgentsVelocityWithIt", GPU),
    ("test_neighbors", "Neighbors.CrowdedCellWithDuplicatesAndTies", GPU),
    ("test_point_grid", "PointGrid.NoPointsAndOnePoint", GPU),
    ("test_step_stages", "StepStages.ModelWithoutMinDistanceCountsStepsOnly", GPU),
    ("test_field_model", "FieldModelReference.TimeVaryingCurlNoiseAndGoalOneStep", GPU),
    ("test_field_model", "FieldModelTest.MinimumDistanceSeparatesIsolatedPairsExactly", GPU),
    ("test_field_model", "FieldModelReference.WhiteNoiseAndGoalOneStep", GPU),
    ("test_force_model", "ForceTerms.InteractionZonesMatchBruteForce", GPU),
    ("test_policy", "PolicyStep.AppliesTheActionsWithEquationTwo", GPU),
    ("test_rl_env", "RlEnv.ObservationsAndRewardsMatchReference", GPU),
    ("test_rl_env", "RlEnv.RagMatchesReference", GPU),
    ("test_swarm_metrics", "SwarmMetrics.NearestNeighbourMatchesBruteForce", GPU),
]

# Cases left out of the Oclgrind gate (too slow under it, or with open
# reports) that still build programs natively: scripts/nvptx_check.py
# --census runs them too, so every GPU-profile program is compiled for NVIDIA.
CENSUS_EXTRA = [
    ("test_noise", "BakedNoise.AgreesWithProceduralAtNodesAndWithinTrilinearErrorBetween", GPU),
    ("test_sdf", "Sdf.MeshWithAHole", GPU),
    ("test_path_field", "PathModel.GlobalVelocityMatchesTheHostReference", GPU),
    ("test_path_field", "PathModel.BakedMeshNoiseMatchesProcedural", GPU),
    ("test_path_chasing", "PathChasing.MovingTheTargetMatchesAFreshBuild", GPU),
    ("test_force_model", "ForceModel.MinDistanceMatchesItsReference", GPU),
    ("test_energy_model", "EnergyModel.EveryTermMatchesTheHostReference", GPU),
    ("test_policy", "PolicyObserve.GridObservationsEqualTheAllPairsReference", GPU),
    ("test_policy", "PolicyMlp.KernelMatchesReference", GPU),
    ("test_force_obstacles", "ForceMeshObstacles.SampledDistanceOfASphereMeshIsWithinACell", GPU),
]

# Kernels no case runs, and why (they are compiled for NVIDIA all the same,
# docs/benchmarks.md).  The check fails on any other kernel no case ran.
NOT_RUN = {
    "noise_bake": "the smallest baking test (BakedNoise.*) took over 240 s under Oclgrind on 2 shared cores",
    "sdf_band": "the smallest signed-distance test (Sdf.MeshWithAHole) took over 240 s under Oclgrind",
    "min_distance_enforce_w": "MinDistance.WideKernelEqualsScalarKernelBitwise took over 300 s under Oclgrind",
    "path_noise_bake": "PathModel.BakedMeshNoiseMatchesProcedural took over 200 s under Oclgrind",
    "path_noise_rebake_box": "PathChasing.MovingTheTargetMatchesAFreshBuild took over 200 s under Oclgrind",
    "path_model_advance": "every path model test took over 200 s under Oclgrind (the cost field's fast "
                          "marching and noise bake come first)",
    "path_model_advance_w": "as path_model_advance",
    "force_model_force_w": "ForceModel.WideKernelMatchesTheScalarOne: reports not yet analysed "
                           "(docs/reliability.md), left out of the gate",
    "force_model_repulsion_w": "as force_model_force_w",
    "energy_select": "EnergyModel.EveryTermMatchesTheHostReference: 20 reports not yet analysed "
                     "(docs/reliability.md), left out of the gate",
    "energy_prepare": "as energy_select",
    "energy_centre_final": "as energy_select",
    "policy_observe": "PolicyObserve.GridObservationsEqualTheAllPairsReference: 20 reports in scatter_xyz "
                      "not yet analysed (docs/reliability.md), left out of the gate",
    "policy_observe_w": "as policy_observe",
    "metrics_histogram": "SwarmMetrics.DeviceMatchesTheHostReference... (CPU profile) failed under Oclgrind "
                         "without a report: not yet analysed",
    "force_model_mesh_distance": "ForceMeshObstacles.SampledDistance... took over 200 s under Oclgrind",
    "force_model_mde": "its case (ForceModel.MinDistanceMatchesItsReference) has open reports",
    "force_model_integrate": "as force_model_mde",
    "force_model_project": "as force_model_mde",
    "field_model_advance_w": "no CPU-profile field model case in the list yet (the one tried has open "
                             "reports in min_distance_enforce_w)",
    "noise_sample_w": "as field_model_advance_w",
    "integrate_ballistic": "no case without a model in the list yet",
}
# PolicyMlp.KernelMatchesReference (over 200 s) is left out too; policy_mlp
# runs in PolicyStep.AppliesTheActionsWithEquationTwo.
# Left out of the gate, with open reports (docs/reliability.md, "Oclgrind"):
# Neighbors.SparseSwarmNearestSearchesFar, PointGrid.GivenGeometryMatchesBruteForce,
# ForceModel.MinDistanceMatchesItsReference (grid_keys_count after a second
# swarm or grid in one process), FieldModelTest.MinimumDistanceSeparates...
# in the CPU profile (min_distance_enforce_w).

REPORT = re.compile(r"^(Uninitialized value|Controlflow depends on uninitialized|Invalid (read|write)|"
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
           "-cl-opt-disable -DSWCL_NO_ALWAYS_INLINE",
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
    ap.add_argument("--timeout", type=int, default=400, help="seconds per case")
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

    if not args.only:
        missing = sorted(source_kernels(args.kernels) - ran_all - set(NOT_RUN))
        if missing:
            failures.append("kernels no case ran: " + ", ".join(missing))
    print(f"oclgrind check: {len(jobs)} cases, {len(ran_all)} kernels ran, {time.time() - t_start:.0f} s "
          f"({args.jobs} at a time); logs in {log_dir}")
    if failures:
        print("oclgrind check FAILED:")
        for f in failures:
            print("  " + f.replace("\n", "\n    "))
        return 1
    print("oclgrind check passed: no report from --data-races --uninitialized; every kernel ran but "
          + ", ".join(f"{k} ({why})" for k, why in sorted(NOT_RUN.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
