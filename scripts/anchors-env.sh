# Sourced by the scripts that compare penumbra with ../shared/anchors
# (bench-vs-embree.sh, bench-vs-mitsuba.sh), from the repository root, with
# OUT set and the script's arguments as "$@": the anchors' folder and
# Python (../shared/anchors/setup.sh makes the venv), the LLVM Mitsuba's
# llvm variants need, the output folder, and the penumbra binaries to run
# (a fresh release build when none is given).
ANCHORS=$(cd ../shared/anchors && pwd)
PY=${PY:-/opt/anchors-venv/bin/python}
export DRJIT_LIBLLVM_PATH=${DRJIT_LIBLLVM_PATH:-/usr/lib/x86_64-linux-gnu/libLLVM-19.so}
export ANCHORS_OUT=$OUT
mkdir -p "$OUT"
if [ $# -eq 0 ]; then
  cargo build --release -p penumbra-cli
  set -- "$PWD/target/release/penumbra"
fi
