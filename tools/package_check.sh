#!/usr/bin/env bash
# Packages the six shipped crates as a registry would receive them and builds each package on
# its own (cargo's verification: the packaged sources only, with the siblings as packaged
# alongside), so a file left out of a package or a dependency only the workspace provides
# fails here. A developer script, not run by CI: it needs the crates.io index and takes a few
# minutes. The metadata itself is checked by `tests/downstream/tests/suite/publishable.rs`.
#
# Usage: tools/package_check.sh [extra cargo package flags, e.g. --allow-dirty]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo package "$@" \
    -p dyngen-runtime -p dyngen-model -p dyngen-codegen -p dyngen-control -p dyngen-identify -p dyngen-cli \
    --target-dir target/package-check
ls -l target/package-check/package/*.crate
