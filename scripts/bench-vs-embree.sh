#!/usr/bin/env bash
# Closest-hit throughput of penumbra and Embree on exactly the same rays, in
# one run: penumbra's bench sphere (~1M triangles) is exported as an OBJ,
# ../shared/anchors/bench_embree.py makes the coherent (camera) and random
# incoherent ray sets from it, and the incoherent rays again sorted by the
# triangle they start on (`incoherent_sorted`: neighbouring origins, random
# directions; the anchors' "extra" set, kinder to caches), and times
# Embree 3 through Mitsuba on each, then
# `penumbra bench --rays` traces the same files, one ray at a time
# (`file`), interleaved (`file-interleaved`) and in packets of 16
# consecutive rays (`file-packets`). Needs the anchors' venv
# (../shared/anchors/setup.sh).
#
#   scripts/bench-vs-embree.sh [PENUMBRA_BINARY...]   (default: the PGO build; PGO=0: the release build)
#
# SCENE=cornell traces the Cornell box of ../shared/reference instead (its
# 32 triangles merged into one OBJ, 2048² camera rays and as many random
# ones): a tree that fits the L1 cache, as in the path-tracing benchmark,
# where memory no longer hides the traversal's own cost.
#
# EMBREE_SINGLE=1 also times Embree 4 one ray at a time on one thread
# (rtcIntersect1 through embreex, the anchors' other backend) and
# penumbra's `bench --threads 1` on the same rays: single ray against
# single ray, where the default compares with Mitsuba's 16-wide packets on
# all cores.
# Results: $OUT (default /tmp/bench-vs-embree): results.jsonl (Embree),
# penumbra.txt, and summary.txt: each binary's Mrays/s (and build time)
# over its runs, as ratios to Embree's in the same run.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/bench-vs-embree}
source scripts/anchors-env.sh
if [ "${SCENE:-}" = cornell ]; then
  # bench_embree.py traces its scene's first object: one OBJ of all of them.
  "$PY" - "$(cd ../shared/reference/cornell && pwd)" "$OUT" <<'PY'
import json, os, sys
src, out = sys.argv[1:3]
scene = json.load(open(os.path.join(src, "scene.json")))
vertices, faces = [], []
for obj in scene["objects"]:
    base = len(vertices)
    for line in open(os.path.join(src, obj["mesh"])):
        p = line.split()
        if p and p[0] == "v":
            vertices.append(p[1:4])
        elif p and p[0] == "f":
            f = [int(x.split("/")[0]) + base for x in p[1:]]
            faces += [(f[0], f[i], f[i + 1]) for i in range(1, len(f) - 1)]
with open(os.path.join(out, "mesh.obj"), "w") as o:
    o.writelines("v %s\n" % " ".join(v) for v in vertices)
    o.writelines("f %d %d %d\n" % f for f in faces)
scene["camera"]["resolution"] = [2048, 2048]
scene["objects"] = [{"name": "cornell", "mesh": os.path.join(out, "mesh.obj"),
                     "albedo": [0.8, 0.8, 0.8], "emission": [0, 0, 0], "smooth": False}]
json.dump(scene, open(os.path.join(out, "scene.json"), "w"))
PY
else
  "$1" bench --spp 0 --write-mesh "$OUT/mesh.obj" >/dev/null
  cat > "$OUT/scene.json" <<JSON
{"name": "benchsphere", "units": "m",
 "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 42.0, "resolution": [1024, 1024]},
 "lights": [{"type": "directional", "direction": [0.0, -0.6, -0.8], "irradiance": [3, 3, 3]}],
 "background": [0, 0, 0],
 "objects": [{"name": "sphere", "mesh": "$OUT/mesh.obj", "albedo": [0.8, 0.8, 0.8], "emission": [0, 0, 0], "smooth": false}]}
JSON
fi
"$PY" "$ANCHORS/bench_embree.py" --scene "$OUT/scene.json" --export-rays "$OUT/rays"
"$PY" "$ANCHORS/bench_embree.py" --backend mitsuba --runs 5 --scene "$OUT/scene.json"
: > "$OUT/penumbra.txt"
binaries=("$@")
trace_sets() { # LABEL BENCH-OPTION...: three runs of each set with each binary
  local label=$1
  shift
  for bin in "${binaries[@]}"; do
    for set in coherent incoherent incoherent_sorted; do
      for run in 1 2 3; do
        line=$("$bin" bench "$@" --mesh "$OUT/mesh.obj" --rays "$OUT/rays/$set.rays" --spp 0 2>&1 | grep -E '^(build|file)' | tr -s ' ' | tr '\n' ' ')
        echo "$bin $set${label} run $run: $line" | tee -a "$OUT/penumbra.txt"
      done
    done
  done
}
trace_sets ""
if [ "${EMBREE_SINGLE:-0}" = 1 ]; then
  "$PY" "$ANCHORS/bench_embree.py" --backend embreex --runs 3 --scene "$OUT/scene.json" > /dev/null
  trace_sets " one thread," --threads 1
fi

# Each binary's range over its runs as a ratio to Embree's median in this
# run (the last measures of each tool in results.jsonl, which keeps every
# run's), with Embree's own figures: the issue's table.
python3 - "$OUT/results.jsonl" "$OUT/penumbra.txt" <<'PY' | tee "$OUT/summary.txt"
import json, re, sys
embree = {}
for line in open(sys.argv[1]):
    if line.startswith("{"):
        r = json.loads(line)
        if "measure" in r:
            embree[("one thread" if r["tool"].startswith("embreex") else "all cores", r["measure"])] = r
runs = {}
for line in open(sys.argv[2]):
    m = re.match(r"(\S+) (\S+?)( one thread,)? run \d+: (.*)", line)
    if not m:
        continue
    key = (m[1], "one thread" if m[3] else "all cores", m[2])
    for kind, seconds, rate in re.findall(r"(build|file\S*) (\S+) s (\S+) (?:Mtris|Mrays)/s", m[4]):
        runs.setdefault(key, {}).setdefault(kind, []).append((float(seconds), float(rate)))
span = lambda xs: f"{min(xs):.2f}-{max(xs):.2f}"
all_cores_first = lambda item: (item[0][1] != "all cores", item[0])
names = {"file": "one at a time", "file-interleaved": "interleaved", "file-packets": "packets"}
for (binary, threads, ray_set), kinds in sorted(runs.items(), key=all_cores_first):
    base = embree.get((threads, "trace_" + ray_set))
    parts = []
    for kind, label in names.items():
        if kind in kinds:
            rate = [r for _, r in kinds[kind]]
            ratio = f" ({span([x / base['mrays_per_s'] for x in rate])}x)" if base else ""
            parts.append(f"{label} {span(rate)}{ratio}")
    print(f"{binary}, {threads}, {ray_set}: " + ", ".join(parts)
          + (f"; Embree {base['mrays_per_s']:.2f} Mrays/s" if base else ""))
builds = {}
for (binary, threads, _), kinds in runs.items():
    builds.setdefault((binary, threads), []).extend(s for s, _ in kinds.get("build", []))
for (binary, threads), seconds in sorted(builds.items(), key=all_cores_first):
    build = embree.get((threads, "bvh_build"))
    if seconds and build:
        print(f"{binary}, {threads}, build (every run): {span(seconds)} s, "
              f"{span([build['seconds'] / s for s in seconds])}x Embree's rate ({build['seconds']:.3f} s)")
PY
