# Sourced by the scripts that compare penumbra with ../shared/anchors
# (bench-vs-embree.sh, bench-vs-mitsuba.sh), from the repository root, with
# OUT set and the script's arguments as "$@": the anchors' folder and
# Python (../shared/anchors/setup.sh makes the venv), the LLVM Mitsuba's
# llvm variants need, the output folder, and the penumbra binaries to run.
# When none is given: the profile-guided build of the current sources
# (scripts/build-pgo.sh, 8-12 % faster path tracing than the plain release
# build, the same images; about ten minutes the first time, nothing when
# the sources are those of its last run), or with PGO=0 the plain release
# build (`cargo build --release`, what scripts/render.sh runs).
ANCHORS=$(cd ../shared/anchors && pwd)
PY=${PY:-/opt/anchors-venv/bin/python}
export DRJIT_LIBLLVM_PATH=${DRJIT_LIBLLVM_PATH:-/usr/lib/x86_64-linux-gnu/libLLVM-19.so}
export ANCHORS_OUT=$OUT
mkdir -p "$OUT"
if [ $# -eq 0 ]; then
  if [ "${PGO:-1}" = 1 ]; then
    # An assignment first: `set -- "$(…)"` would go on after a failed build
    # (set's own status is 0), with an empty binary path.
    pgo_bin=$(scripts/build-pgo.sh)
    set -- "$pgo_bin"
  else
    cargo build --release -p penumbra-cli
    set -- "$PWD/target/release/penumbra"
  fi
fi
