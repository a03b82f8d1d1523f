#!/usr/bin/env bash
# The C library benchmark: each function of the Panda and the Solo-12 from C++ through the
# generated C library, against the same function called from Rust, per state, in one run
# (benchmarks/c_library/bench.cpp). Release builds (a default build: no target-cpu flag, as a
# user's), pinned to one core when taskset is there. A developer script, never run by CI: the
# first run builds both robots in release (a few minutes).
#
# Usage: benchmarks/c_library/run.sh [ROUNDS]   (default 21)
# Work files go to target/c-library-bench/.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
work="$repo/target/c-library-bench"
rounds="${1:-21}"
mkdir -p "$work/robots"

cargo build --quiet --release -p dyngen-cli --manifest-path "$repo/Cargo.toml"
for robot in panda solo12; do
  "$repo/target/release/dyngen" gen "$repo/robots/$robot.yaml" --c-library "$work/robots/$robot" \
    --runtime-path "$repo/runtime"
  cp "$repo/Cargo.lock" "$work/robots/$robot/Cargo.lock"
done
mkdir -p "$work/rust_side/src"
sed "s|@RUNTIME@|$repo/runtime|" "$repo/benchmarks/c_library/rust_side/Cargo.toml" > "$work/rust_side/Cargo.toml"
cp "$repo/benchmarks/c_library/rust_side/src/lib.rs" "$work/rust_side/src/lib.rs"
cp "$repo/Cargo.lock" "$work/rust_side/Cargo.lock"

cmake -S "$repo/benchmarks/c_library" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/robots/panda;$work/robots/solo12" -DDYNGEN_BENCH_ROBOTS="panda;solo12" \
  -DDYNGEN_BENCH_ROBOTS_DIR="$work/robots" -DDYNGEN_BENCH_RUST_SIDE="$work/rust_side" \
  -DDYNGEN_CARGO_TARGET_DIR="$work/cargo" > /dev/null
cmake --build "$work/build" -j 2

pin=()
if command -v taskset > /dev/null; then pin=(taskset -c 1); fi
"${pin[@]}" "$work/build/bench" "$rounds" \
  "panda=$work/cargo/release/libpanda_dynamics.so" "solo12=$work/cargo/release/libsolo12_dynamics.so"
