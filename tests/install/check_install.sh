#!/usr/bin/env bash
# Installs the built library into a scratch prefix, then builds the C example
# as C99 twice against the installed files only: with find_package(swarmcl)
# and with pkg-config; both binaries must run.
set -euo pipefail
src=$1
build=$2
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
test -f "$prefix/include/swarmcl/swarmcl.h"

# 1. CMake package
cmake -S "$src/examples/c" -B "$prefix/example-build" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$prefix/example-build" >/dev/null
LD_LIBRARY_PATH="$prefix/lib:${LD_LIBRARY_PATH:-}" "$prefix/example-build/nearest_neighbors" 2000 | tee "$prefix/out1"
grep -q "nearest-neighbour distance" "$prefix/out1"

# 2. pkg-config, plain cc in strict C99
libdir=$(ls -d "$prefix"/lib*/pkgconfig | head -1)
PKG_CONFIG_PATH="$libdir" cc -std=c99 -Wall -Wextra -pedantic -Werror "$src/examples/c/nearest_neighbors.c" \
    $(PKG_CONFIG_PATH="$libdir" pkg-config --cflags --libs swarmcl) -lm -o "$prefix/nn_pc"
LD_LIBRARY_PATH="$(dirname "$libdir"):${LD_LIBRARY_PATH:-}" "$prefix/nn_pc" 500 | grep -q "agents: 500"
echo "installed package OK: CMake package and pkg-config builds of the C example run"
