#!/usr/bin/env bash
# Installs what swarmcl needs on Debian/Ubuntu, and nothing when it is all
# there already (safe to run again).  Uses sudo when not root.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  # scripts/test.sh: the Python package's build reuses build/'s objects
  ccache
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  libglm-dev libgtest-dev libnanoflann-dev libnoise-dev nlohmann-json3-dev
  libtinyobjloader-dev zlib1g-dev libcli11-dev libopenvdb-dev libboost-dev python3-scikit-fmm
  python3 python3-pip python3-venv
  openmpi-bin
  # issue 27: every kernel under Oclgrind (ctest oclgrind.kernels), and
  # compiled for NVIDIA by clang + libclc (ctest nvptx.compile; ptxas comes
  # with the CUDA toolkit, not from here: without it that test is skipped)
  oclgrind clang-15 libclc-15 libclc-15-dev
  # the sanitized suite (scripts/asan.sh) is built with clang-15; llvm-15 has
  # the llvm-symbolizer its runtime names functions and lines with
  llvm-15
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "bootstrap: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
