#!/usr/bin/env python3
"""Compiles every swarmcl kernel program for NVIDIA without a GPU (issue 27).

Input: a folder of programs exactly as the host built them
($SWARMCL_PROGRAM_DUMP_DIR, written by host/device/context.cpp: includes
expanded, the first line "// swarmcl-build-options: <options>" with the GPU
profile's defines); --census BUILD fills it first by running a fixed list of
small GoogleTest cases in the GPU profile (ctest nvptx.compile does).  Each program is compiled by clang for
nvptx64-nvidia-nvcl with libclc's OpenCL C library linked in, then assembled
by ptxas -arch=sm_90 -v.  Per kernel: registers, spill stores/loads, stack
frame (local memory) — the largest over the program variants (defines) that
were built.

Fails (exit 1) when a program does not compile or assemble, when a kernel of
kernels/ (SWCL_KERNEL bodies count as name and name_w) was compiled by no
program and is not CPU-only, or when a kernel spills or uses more than 128
registers without an explanation in EXPLAINED below.  Exit 77 (ctest's
SKIP_RETURN_CODE) with a message when ptxas, clang or libclc is absent.

Writes --json (per kernel and per variant) and --markdown (the table in
docs/benchmarks.md, "NVIDIA compile (sm_90)").
"""
import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

# Kernels the GPU profile never builds: the explicit-width twins (8 or 16
# agents per work-item) run on CPU devices only (docs/architecture.md,
# "Device profiles"); metrics_histogram counts per-chunk copies on CPUs (one
# atomic histogram on GPUs).
CPU_ONLY = {
    "min_distance_enforce_w", "noise_sample_w", "field_model_advance_w", "path_model_advance_w",
    "force_model_force_w", "force_model_repulsion_w", "policy_observe_w", "metrics_histogram",
    "metrics_nearest_w", "metrics_sample_w", "neighbor_count_w",
}

# Builds the GPU profile never makes: the policy MLP's lanes (PM_W 8 or 16
# agents per work-item, the CPU's SIMD width; GPUs take PM_W 1,
# host/models/policy_model.cpp), which the width tests build on any device.
# Only their CPU-only kernels (policy_observe_w) are counted from them.
CPU_ONLY_DEFINES = {"-DPM_W=8", "-DPM_W=16"}

# Kernels allowed to spill or to exceed 128 registers, with the reason
# (docs/benchmarks.md, "NVIDIA compile (sm_90)", repeats it).
EXPLAINED = {
    "energy_select": "one neighbour pass adds every neighbour's terms to all of the agent's candidate "
                     "velocities at once: two private arrays of EM_MAX_CAND floats (rep, oa: Eq. 4 and 6 per "
                     "candidate) live in local memory (stack) on a GPU.  Walking the neighbours once per chunk "
                     "of candidates would fit registers, with the same sums in the same order, at the cost of "
                     "re-reading the neighbours per chunk; to be decided on GPU timings",
}

REG_LIMIT = 128
# The name of a kernel's -DSWCL_WORLDS build in the report.
WORLDS_SUFFIX = " [worlds]"


def find_tool(names, extra_dirs=()):
    for n in names:
        p = shutil.which(n)
        if p:
            return p
    for d in extra_dirs:
        for n in names:
            p = os.path.join(d, n)
            if os.path.isfile(p) and os.access(p, os.X_OK):
                return p
    return None


def find_clang_and_libclc():
    """A clang whose major version has a libclc nvptx64 bitcode beside it."""
    cands = []
    for v in (19, 18, 17, 16, 15, 14):
        c = find_tool([f"clang-{v}"], [f"/usr/lib/llvm-{v}/bin"])
        if c:
            cands.append((v, c))
    for v, c in cands:
        for lib in (f"/usr/lib/llvm-{v}/lib/clc/nvptx64--nvidiacl.bc", "/usr/lib/clc/nvptx64--nvidiacl.bc",
                    f"/usr/share/clc/nvptx64--nvidiacl.bc"):
            if os.path.isfile(lib):
                inc = [d for d in (f"/usr/lib/llvm-{v}/include", "/usr/include") if os.path.isfile(os.path.join(d, "clc", "clc.h"))]
                if inc:
                    return c, v, lib, inc[0]
    return None


def source_kernels(kernel_dir):
    names = set()
    for path in glob.glob(os.path.join(kernel_dir, "**", "*.cl"), recursive=True):
        text = open(path, encoding="utf-8").read()
        text = re.sub(r"//[^\n]*", "", text)
        for m in re.finditer(r"__kernel\s+void\s+(?!SWCL_KERNEL\b)([A-Za-z_]\w*)", text):
            names.add(m.group(1))
        for m in re.finditer(r"\bvoid\s+SWCL_KERNEL\((\w+)\)", text):
            names.add(m.group(1))
            names.add(m.group(1) + "_w")
    return names


def parse_ptxas(log):
    """{kernel: {registers, spill_stores, spill_loads, stack_bytes}} from ptxas -v."""
    out = {}
    current = None
    for line in log.splitlines():
        m = re.search(r"Compiling entry function '([^']+)'", line)
        if m:
            current = m.group(1)
            out[current] = {"registers": 0, "spill_stores": 0, "spill_loads": 0, "stack_bytes": 0}
            continue
        if current is None:
            continue
        m = re.search(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads", line)
        if m:
            out[current]["stack_bytes"] = int(m.group(1))
            out[current]["spill_stores"] = int(m.group(2))
            out[current]["spill_loads"] = int(m.group(3))
        m = re.search(r"Used (\d+) registers", line)
        if m:
            out[current]["registers"] = int(m.group(1))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dump_dir", help="folder of programs written with $SWARMCL_PROGRAM_DUMP_DIR")
    ap.add_argument("--kernels", required=True, help="the kernels/ source folder (for the list of kernels)")
    ap.add_argument("--arch", default="sm_90")
    ap.add_argument("--json", help="write per-kernel figures here")
    ap.add_argument("--markdown", help="write the docs table here")
    ap.add_argument("--no-coverage", action="store_true", help="do not require every kernel to be compiled")
    ap.add_argument("--census", metavar="BUILD", help="first fill dump_dir by running natively, in the GPU "
                    "profile, the GoogleTest cases scripts/oclgrind_check.py lists (CASES and CENSUS_EXTRA; a "
                    "few minutes on PoCL)")
    args = ap.parse_args()

    if args.census:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import oclgrind_check
        shutil.rmtree(args.dump_dir, ignore_errors=True)
        env = dict(os.environ, SWARMCL_PROGRAM_DUMP_DIR=os.path.abspath(args.dump_dir), SWARMCL_DEVICE_PROFILE="gpu")
        for binary, gfilter, profile in oclgrind_check.CASES + oclgrind_check.CENSUS_EXTRA:
            if profile["SWARMCL_DEVICE_PROFILE"] != "gpu":
                continue
            r = subprocess.run([os.path.join(args.census, "tests", binary), f"--gtest_filter={gfilter or '*'}"],
                               env=env, capture_output=True, text=True)
            if r.returncode != 0:
                print(f"nvptx check FAILED: census case {binary} {gfilter} failed:\n{r.stdout[-1000:]}")
                return 1

    ptxas = find_tool(["ptxas"], [os.path.join(os.environ.get("CUDA_HOME", "/usr/local/cuda"), "bin"), "/usr/local/cuda/bin"])
    if not ptxas:
        print("nvptx check SKIPPED: ptxas (CUDA toolkit) not found on PATH, $CUDA_HOME/bin or /usr/local/cuda/bin")
        return 77
    found = find_clang_and_libclc()
    if not found:
        print("nvptx check SKIPPED: no clang with libclc's nvptx64--nvidiacl.bc and clc/clc.h "
              "(Debian: apt-get install clang-15 libclc-15 libclc-15-dev)")
        return 77
    clang, clang_major, libclc, clc_include = found
    ptxas_version = subprocess.run([ptxas, "--version"], capture_output=True, text=True).stdout.strip().splitlines()[-1]

    programs = sorted(glob.glob(os.path.join(args.dump_dir, "*.cl")))
    if not programs:
        print(f"nvptx check FAILED: no programs in {args.dump_dir}; they are written by the GPU-profile tests "
              "(ctest -L gpu_profile) with SWARMCL_PROGRAM_DUMP_DIR set")
        return 1

    # clang 15 knows sm_86 at most: the PTX is generated for it and ptxas
    # assembles it for the requested architecture (PTX is forward compatible).
    ptx_cpu = "sm_86" if clang_major < 16 else "sm_90"
    failures = []
    variants = []
    per_kernel = {}
    with tempfile.TemporaryDirectory() as tmp:
        for prog in programs:
            first = open(prog, encoding="utf-8").readline()
            m = re.match(r"// swarmcl-build-options: (.*)", first)
            if not m:
                failures.append(f"{prog}: no build-options line")
                continue
            options = m.group(1).split()
            cpu_lanes = bool(CPU_ONLY_DEFINES.intersection(options))
            base = os.path.basename(prog)[:-3]
            file = re.sub(r"-[0-9a-f]{16}$", "", base) + ".cl"
            ptx = os.path.join(tmp, base + ".ptx")
            cmd = [clang, "-target", "nvptx64-nvidia-nvcl", f"-march={ptx_cpu}", "-x", "cl", "-O2",
                   "-Dcl_clang_storage_class_specifiers", "-isystem", clc_include, "-include", "clc/clc.h",
                   "-Wno-linker-warnings", "-Xclang", "-mlink-builtin-bitcode", "-Xclang", libclc,
                   *options, "-S", prog, "-o", ptx]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                err = next((l for l in r.stderr.splitlines() if "error" in l), r.stderr.strip()[:300])
                failures.append(f"clang refused {file} ({' '.join(options)}): {err}")
                continue
            r = subprocess.run([ptxas, f"-arch={args.arch}", "-v", ptx, "-o", os.devnull], capture_output=True, text=True)
            if r.returncode != 0:
                err = next((l for l in (r.stderr + r.stdout).splitlines() if "error" in l.lower()), r.stderr.strip()[:300])
                failures.append(f"ptxas refused {file} ({' '.join(options)}): {err}")
                continue
            stats = parse_ptxas(r.stderr + r.stdout)
            defines = [o for o in options if o.startswith("-D") and not o.startswith("-DSWCL_CPU_PROFILE")]
            variants.append({"program": file, "defines": defines, "kernels": stats})
            for k, s in stats.items():
                if cpu_lanes and k not in CPU_ONLY:
                    continue  # a GPU builds it with PM_W 1: checked in that variant
                # A swarm of several worlds builds its kernels with the world
                # offsets (-DSWCL_WORLDS, docs/architecture.md "Worlds"):
                # counted apart, so a one-world kernel keeps its own limit.
                if any(d.startswith("-DSWCL_WORLDS") for d in defines):
                    k += WORLDS_SUFFIX
                e = per_kernel.setdefault(k, {"program": file, "variants": 0, "registers": 0, "spill_stores": 0,
                                              "spill_loads": 0, "stack_bytes": 0})
                e["variants"] += 1
                for f in ("registers", "spill_stores", "spill_loads", "stack_bytes"):
                    e[f] = max(e[f], s[f])

    expected = source_kernels(args.kernels) - CPU_ONLY
    missing = sorted(expected - set(per_kernel))
    if missing and not args.no_coverage:
        failures.append("kernels no GPU-profile program compiled (their tests did not run, or a kernel was added "
                        "without a GPU-profile test): " + ", ".join(missing))
    for k, e in sorted(per_kernel.items()):
        if k.removesuffix(WORLDS_SUFFIX) in CPU_ONLY:
            continue  # compiled with its program, never launched on a GPU
        bad = []
        if e["registers"] > REG_LIMIT:
            bad.append(f"{e['registers']} registers > {REG_LIMIT}")
        if e["spill_stores"] or e["spill_loads"]:
            bad.append(f"spills {e['spill_stores']} B stored / {e['spill_loads']} B loaded")
        if bad and k not in EXPLAINED:
            failures.append(f"{k} ({e['program']}): " + ", ".join(bad) + " (rework it, or explain it in EXPLAINED)")

    report = {"arch": args.arch, "ptx_target": ptx_cpu, "clang": os.path.basename(clang), "ptxas": ptxas_version,
              "libclc": os.path.basename(libclc), "programs": len(programs), "kernels": per_kernel,
              "variants": variants, "cpu_only_not_compiled": sorted(CPU_ONLY),
              "cpu_only_defines": sorted(CPU_ONLY_DEFINES), "failures": failures}
    if args.json:
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1, sort_keys=True)
    if args.markdown:
        lines = [f"| kernel | program | variants | registers | spill stores / loads (B) | stack frame (B) |",
                 "|---|---|---:|---:|---:|---:|"]
        for k, e in sorted(per_kernel.items(), key=lambda kv: (kv[1]["program"], kv[0])):
            base = k.removesuffix(WORLDS_SUFFIX)
            note = " (CPU profile only)" if base in CPU_ONLY else (" (explained below)" if k in EXPLAINED else "")
            note = (" (worlds)" if base != k else "") + note
            lines.append(f"| `{base}`{note} | {e['program']} | {e['variants']} | {e['registers']} | "
                         f"{e['spill_stores']} / {e['spill_loads']} | {e['stack_bytes']} |")
        with open(args.markdown, "w") as f:
            f.write("\n".join(lines) + "\n")

    print(f"nvptx check: {len(programs)} programs, {len(per_kernel)} kernels compiled by {os.path.basename(clang)} "
          f"(PTX {ptx_cpu}, libclc) and {ptxas_version} for {args.arch}")
    for k, e in sorted(per_kernel.items(), key=lambda kv: -kv[1]["registers"])[:8]:
        print(f"  {k:32s} {e['registers']:4d} registers, spills {e['spill_stores']}/{e['spill_loads']} B, "
              f"stack {e['stack_bytes']} B ({e['variants']} variants)")
    if failures:
        print("nvptx check FAILED:")
        for f in failures:
            print("  " + f)
        return 1
    print("nvptx check passed: every GPU-profile kernel compiles and assembles; none spills or exceeds "
          f"{REG_LIMIT} registers but those explained ({', '.join(sorted(EXPLAINED)) or 'none'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
