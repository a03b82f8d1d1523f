#!/bin/sh
# Builds the numeric Pinocchio 4.1 anchor of the named frames (README.md):
#   build/models/<robot>.txt  the Pinocchio models of the committed URDFs (dump_model.py, run
#                             with the venv's Python: the wheel's URDF parser, buildReducedModel)
#   build/bench_frames        header-only Pinocchio, -O3 -march=native, which reads them
#
#   ./build.sh           (the venv /tmp/pinenv; VENV=DIR for another, PREFIX=DIR for its cmeel.prefix)
#
# One compiler process: about 80 s and 2.5 GB of memory (the --param ggc-* trade a little time
# for less memory: 2.9 GB without).
set -eu
cd "$(dirname "$0")"
HERE=$(pwd)
REPO=$(cd ../../.. && pwd)
VENV=${VENV:-/tmp/pinenv}
PREFIX=${PREFIX:-$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"] + "/cmeel.prefix")')}
CXX=${CXX:-g++}
for header in pinocchio/config.hpp eigen3/Eigen/Core; do
    if [ ! -f "$PREFIX/include/$header" ]; then
        echo "missing $PREFIX/include/$header: see README.md (pip install pin==4.1.0 cmeel-eigen==3.4.1 ...)" >&2
        exit 1
    fi
done
mkdir -p build
"$VENV/bin/python" dump_model.py "$REPO" build/models
# The compile definitions of the pinocchio::pinocchio_headers CMake target
# (lib/cmake/pinocchio/pinocchioTargets.cmake). Without PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION
# every algorithm is a template instantiated in this file: header-only, nothing to link.
# -Wno-stringop-overread: GCC 12's false positives inside Eigen's AVX-512 code.
set -x
"$CXX" -std=c++17 -O3 -march=native -DNDEBUG \
    --param ggc-min-expand=20 --param ggc-min-heapsize=65536 \
    -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
    -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 \
    -Wno-stringop-overread \
    -I"$PREFIX/include" -I"$PREFIX/include/eigen3" \
    "$HERE/bench_frames.cpp" -o build/bench_frames
