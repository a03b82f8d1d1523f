#!/bin/sh
# Builds the numeric Pinocchio 4.1 anchor of constrained dynamics (README.md):
#   build/models/<robot>.txt  the Pinocchio models of Solo-12 and the G1 on a free flyer
#                             (dump_model.py, run with the venv's Python)
#   build/bench_contacts      header-only Pinocchio, -O3 -march=native, which reads them
#
#   ./build.sh           (the venv /tmp/pinenv; VENV=DIR for another, PREFIX=DIR for its cmeel.prefix)
#
# One compiler process: about 5 minutes on a 2-vCPU VM, 3 GB of memory.
set -eu
cd "$(dirname "$0")"
. ../common/compile.sh
build_anchor bench_contacts
