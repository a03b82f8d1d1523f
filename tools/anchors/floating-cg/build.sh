#!/usr/bin/env bash
# Builds the Pinocchio + CppADCodeGen anchor of free-flyer robots (README.md):
#   build/models/<robot>.txt      the Pinocchio models (../contacts/dump_model.py)
#   build/gen                     gen.cpp: Pinocchio on AD<CG<double>>, header-only, -O1
#   build/c/<robot>_<fn>.c        the generated C, and functions.c (the table);
#                                 build/gen_log.txt: tape sizes, C bytes, seconds per function
#   build/bench_floating_cg_native, build/bench_floating_cg_O3
#                                 bench_floating_cg.cpp (numeric Pinocchio, header-only, -O3
#                                 -march=native) linked with the C compiled by gcc -O3
#                                 -march=native, or by gcc -O3; build/compile_<variant>.txt:
#                                 seconds and memory per file
#   then each binary's --check.
#
#   ./build.sh                    every robot (solo12 g1); ROBOTS="solo12" for fewer
#   VENV=DIR / PREFIX=DIR         the venv of pin==4.1.0, cmeel-cppad, cmeel-cppadcodegen
#                                 (default /tmp/cgenv), its cmeel.prefix
#   JOBS=N                        generated files compiled at once (default 1)
#   CC=...                        the C compiler (default gcc)
#   VARIANTS="native"             the variants built (default "native O3"; the G1's O3 build
#                                 of aba_derivatives alone takes 16 minutes and 6 GB)
#
# A step whose output is newer than its inputs is skipped. Times and memory: README.md.
set -euo pipefail
cd "$(dirname "$0")"
VENV=${VENV:-/tmp/cgenv}
. ../common/compile.sh
ROBOTS=${ROBOTS:-solo12 g1}
JOBS=${JOBS:-1}
CC=${CC:-gcc}
if [[ ! -f "$PREFIX/include/cppad/cg.hpp" || ! -f "$PREFIX/include/pinocchio/codegen/cppadcg.hpp" ]]; then
    echo "missing CppADCodeGen under $PREFIX/include: see README.md (pip install cmeel-cppadcodegen ...)" >&2
    exit 1
fi
mkdir -p build/c
export -f compile_anchor
export CXX PREFIX

# Runs a command (a shell function too), then appends `LABEL wall_s cpu_s max_rss_mb` to FILE:
# the wall and processor seconds, and the largest memory of a process it ran.
measured() {
    local label=$1 file=$2
    shift 2
    local times
    times=$(mktemp)
    /usr/bin/time -f "$label %e %U %S %M" -o "$times" bash -c '"$@"' measured "$@"
    awk '{printf "%s %.2f %.2f %.0f\n", $1, $2, $3 + $4, $5 / 1024}' "$times" >> "$file"
    rm -f "$times"
}

newer() { # newer TARGET SOURCE...: TARGET missing or older than a SOURCE
    local target=$1
    shift
    [[ ! -e "$target" ]] && return 0
    for source in "$@"; do [[ "$source" -nt "$target" ]] && return 0; done
    return 1
}

# 1. The models, each replaced only when it changed (the C is generated again when it is).
# shellcheck disable=SC2086
"$PYTHON" ../contacts/dump_model.py "$(cd ../../.. && pwd)" build/models.new $ROBOTS
mkdir -p build/models
for model in build/models.new/*.txt; do
    cmp -s "$model" "build/models/${model##*/}" || mv "$model" build/models/
done
rm -rf build/models.new

# 2. The generator. Header-only as the numeric anchors, -O1: the AD<CG<double>> instantiations
# compile in minutes rather than many at -O3, and run once. -march=x86-64: the C it writes must
# not depend on the CPU it runs on (built for this one, gcc fuses multiplications and additions
# of the model's constants, and the C's last digits and tape change). CppAD's own warnings
# silenced (-w).
if newer build/gen gen.cpp cg_functions.h ../common/model_text.hpp; then
    : > build/compile_gen.txt
    measured gen build/compile_gen.txt compile_anchor "$(pwd)/gen.cpp" build/gen -O1 -march=x86-64 -w
fi

# 3. The C. gen prints per function its tape, temporaries, C bytes and seconds.
models=()
for robot in $ROBOTS; do models+=("build/models/$robot.txt"); done
if newer build/c/functions.c build/gen "${models[@]}"; then
    rm -f build/c/*.c
    # shellcheck disable=SC2086
    build/gen build/models build/c $ROBOTS | tee build/gen_log.txt
fi

# 4. The driver, once for both variants: numeric Pinocchio for this CPU.
if newer build/bench_floating_cg.o bench_floating_cg.cpp cg_functions.h ../common/model_text.hpp \
        ../common/timing.hpp; then
    : > build/compile_driver.txt
    measured driver build/compile_driver.txt compile_anchor "$(pwd)/bench_floating_cg.cpp" \
        build/bench_floating_cg.o -c
fi

# 5. The generated C per variant, each file timed; then the binary and its check.
compile_c() { # compile_c FILE.c, with $CG_CFLAGS into $OBJECTS, timed into $LOG
    local name
    name=$(basename "$1" .c)
    # shellcheck disable=SC2086
    measured "$name" "$LOG" $CC $CG_CFLAGS -DCG_FLAGS="\"$CG_CFLAGS\"" -I. -c "$1" -o "$OBJECTS/$name.o"
}
variant() {
    export CG_CFLAGS=$2 OBJECTS=build/obj_$1 LOG=build/compile_$1.txt CC
    export -f measured compile_c
    mkdir -p "$OBJECTS"
    local stale=() objects=()
    for c in build/c/*.c; do
        objects+=("$OBJECTS/$(basename "$c" .c).o")
        newer "${objects[-1]}" "$c" && stale+=("$c")
    done
    if ((${#stale[@]})); then
        echo "compiling ${#stale[@]} files with $CC $CG_CFLAGS ($JOBS at once)" >&2
        : > "$LOG"
        printf '%s\n' "${stale[@]}" | xargs -P "$JOBS" -I{} bash -c 'compile_c {}'
        awk '{w += $2; c += $3; if ($4 > m) m = $4}
             END {printf "# all: %.1f s wall, %.1f s processor, at most %d MB\n", w, c, m}' \
            "$LOG" >> "$LOG"
    fi
    "$CXX" build/bench_floating_cg.o "${objects[@]}" -o "build/bench_floating_cg_$1" -lm
    "build/bench_floating_cg_$1" build/models --check | tee "build/check_$1.txt"
}
for v in ${VARIANTS:-native O3}; do
    case $v in
        native) variant native "-O3 -march=native" ;;
        O3) variant O3 "-O3" ;;
        *) echo "unknown variant $v (native, O3)" >&2; exit 1 ;;
    esac
done
