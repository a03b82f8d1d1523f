#!/bin/sh
# Builds the numeric Pinocchio 4.1 anchor of constrained dynamics (README.md):
#   build/models/<robot>.txt  the Pinocchio models of Solo-12 and the G1 on a free flyer
#                             (dump_model.py, run with the venv's Python)
#   build/bench_contacts      header-only Pinocchio, -O3 -march=native, which reads them
#
#   ./build.sh           (the venv /tmp/pinenv; VENV=DIR for another, PREFIX=DIR for its cmeel.prefix)
#
# One compiler process: about 2 minutes and 3 GB of memory.
set -eu
cd "$(dirname "$0")"
REPO=$(cd ../../.. && pwd)
. ../common/compile.sh
mkdir -p build
"$PYTHON" dump_model.py "$REPO" build/models
compile_anchor "$(pwd)/bench_contacts.cpp" build/bench_contacts
