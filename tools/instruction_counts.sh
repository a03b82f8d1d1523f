#!/bin/bash
# Instructions per generated function, counted in the compiled code (a native release build),
# one line per function: `count robot function`. Deterministic where timings on a shared host are
# not, and on straight-line kernels a good predictor of their speed ratios (docs/performance-notes.md,
# *Without AVX-512*): compare two versions of the generator by running this in each.
#
#   tools/instruction_counts.sh OUT_DIR [ROBOT ...]     (robots of robots/, default panda ur5 xarm7)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=$(mkdir -p "$1" && cd "$1" && pwd)
shift
robots=${*:-panda ur5 xarm7}
groups=kinematics,dynamics,regressors,base_parameters,forward_dynamics,derivatives

(cd "$repo" && cargo build -q --release -p dyngen-cli)
mkdir -p "$out/src"
cat > "$out/Cargo.toml" <<TOML
[package]
name = "instruction_counts"
version = "0.0.0"
edition = "2021"
publish = false
[dependencies]
dyngen-runtime = { path = "$repo/runtime" }
[workspace]
TOML
: > "$out/src/lib.rs"
for robot in $robots; do
    "$repo/target/release/dyngen" gen "$repo/robots/$robot.yaml" -o "$out/src/$robot.rs" --functions "$groups" > /dev/null
    echo "pub mod $robot;" >> "$out/src/lib.rs"
done
(cd "$out" && RUSTFLAGS="-C target-cpu=native" cargo rustc -q --release --lib -- --emit=obj)
object=$(ls -t "$out"/target/release/deps/*.o | head -1)
# Every function has a section of its own, so a symbol's instructions are those up to the next.
objdump -d --no-show-raw-insn "$object" | awk '
    /^[0-9a-f]+ <.*>:$/ { if (name) print n, name; name = $2; n = 0; next }
    /^ *[0-9a-f]+:\t/ { n++ }
    END { if (name) print n, name }' \
    | sed 's/[<>:]//g' | c++filt \
    | sed -nE 's/^([0-9]+) <instruction_counts::([a-z0-9_]+)::[A-Za-z0-9]+ as dyngen_runtime::.*>::([a-z_]+)::h[0-9a-f]{16}$/\1 \2 \3/p' \
    | sort -k2,3
