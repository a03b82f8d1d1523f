#!/bin/sh
# Builds the numeric Pinocchio 4.1 anchor of the named frames (README.md):
#   build/models/<robot>.txt  the Pinocchio models of the committed URDFs (dump_model.py, run
#                             with the venv's Python: the wheel's URDF parser, buildReducedModel)
#   build/bench_frames        header-only Pinocchio, -O3 -march=native, which reads them
#
#   ./build.sh           (the venv /tmp/pinenv; VENV=DIR for another, PREFIX=DIR for its cmeel.prefix)
#
# One compiler process: about 80 s and 2.5 GB of memory.
set -eu
cd "$(dirname "$0")"
. ../common/compile.sh
build_anchor bench_frames
