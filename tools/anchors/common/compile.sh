# Sourced by the anchors' build.sh: the venv's Python and Pinocchio headers, and how an anchor
# is compiled.
#
#   VENV    the venv of pin==4.1.0 and cmeel-eigen (default /tmp/pinenv)
#   PREFIX  its cmeel.prefix (default: found from the venv's Python)
#   CXX     the compiler (default g++)
VENV=${VENV:-/tmp/pinenv}
PYTHON="$VENV/bin/python"
PREFIX=${PREFIX:-$("$PYTHON" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"] + "/cmeel.prefix")')}
CXX=${CXX:-g++}
for header in pinocchio/config.hpp eigen3/Eigen/Core; do
    if [ ! -f "$PREFIX/include/$header" ]; then
        echo "missing $PREFIX/include/$header: see README.md (pip install pin==4.1.0 cmeel-eigen==3.4.1 ...)" >&2
        exit 1
    fi
done

# compile_anchor SOURCE OUTPUT [FLAG...]: header-only Pinocchio, -O3 -march=native (FLAG: more,
# e.g. -c for an object file). The definitions are
# those of the pinocchio::pinocchio_headers CMake target (lib/cmake/pinocchio/pinocchioTargets.cmake);
# without PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION every algorithm is a template instantiated in
# SOURCE: nothing to link. The --param ggc-* trade a little time for less memory (the frames
# anchor: 2.5 GB, 2.9 GB without). -Wno-stringop-overread: GCC 12's false positives inside
# Eigen's AVX-512 code.
compile_anchor() {
    (
        source=$1 output=$2
        shift 2
        set -x
        "$CXX" -std=c++17 -O3 -march=native -DNDEBUG \
            --param ggc-min-expand=20 --param ggc-min-heapsize=65536 \
            -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
            -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 \
            -Wno-stringop-overread \
            -I"$PREFIX/include" -I"$PREFIX/include/eigen3" \
            "$source" -o "$output" "$@"
    )
}

# build_anchor NAME, from an anchor's directory: build/models/ (its dump_model.py, given the
# repository's root) and build/NAME from NAME.cpp.
build_anchor() {
    mkdir -p build
    "$PYTHON" dump_model.py "$(cd ../../.. && pwd)" build/models
    compile_anchor "$(pwd)/$1.cpp" "build/$1"
}
