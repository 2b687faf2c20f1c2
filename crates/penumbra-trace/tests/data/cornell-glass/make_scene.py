#!/usr/bin/env python3
"""Writes the glass-sphere Cornell box: sphere.obj (an icosphere with
vertex normals), scene.json (the neutral format of ../shared/anchors, for
Mitsuba) and scene.toml (penumbra), from the reference Cornell box's wall,
light and short-block OBJs (copied from ../shared/reference/cornell). The
tall block is replaced by a smooth glass sphere (ior 1.5) resting on the
floor.

The reference image is rendered once with ../shared/anchors (see README.md
in this folder); the test reads it, it never runs Mitsuba."""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # ../icosphere.py
from icosphere import icosphere  # noqa: E402

CENTER = (370.0, 111.0, 330.0)  # 1 mm above the floor: no coplanar contact
RADIUS = 110.0
LEVELS = 4  # 20 · 4⁴ = 5120 triangles
RESOLUTION = (256, 256)
WHITE = [0.885809, 0.698859, 0.666422]
WALLS = [
    ("floor", WHITE), ("ceiling", WHITE), ("backwall", WHITE),
    ("redwall", [0.570068, 0.0430135, 0.0443706]),
    ("greenwall", [0.105421, 0.37798, 0.076425]), ("shortbox", WHITE),
]
LIGHT = [18.387, 13.9873, 6.75357]


def main():
    v, f = icosphere(LEVELS)
    with open(os.path.join(HERE, "sphere.obj"), "w") as o:
        o.write("# glass sphere: icosphere, %d triangles, outward winding and normals\n" % len(f))
        for p in v:
            o.write("v %.6f %.6f %.6f\n" % tuple(c + RADIUS * x for c, x in zip(CENTER, p)))
        for p in v:
            o.write("vn %.6f %.6f %.6f\n" % p)
        for a, b, c in f:
            o.write("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1))
    camera = {"position": [278, 273, -800], "look_at": [278, 273, -799], "up": [0, 1, 0],
              "fov_y_deg": 39.30764811610662}
    objects = [{"name": n, "mesh": n + ".obj", "albedo": a, "emission": [0, 0, 0], "smooth": False}
               for n, a in WALLS]
    objects.append({"name": "light", "mesh": "light.obj", "albedo": [0, 0, 0], "emission": LIGHT,
                    "smooth": False})
    objects.append({"name": "sphere", "mesh": "sphere.obj", "albedo": [0, 0, 0], "emission": [0, 0, 0],
                    "smooth": True, "material": {"type": "dielectric", "ior": 1.5}})
    scene = {"name": "cornell-glass", "units": "mm", "camera": dict(camera, resolution=list(RESOLUTION)),
             "lights": [], "background": [0, 0, 0], "objects": objects}
    with open(os.path.join(HERE, "scene.json"), "w") as o:
        json.dump(scene, o, indent=1)
        o.write("\n")
    toml = ["# The Cornell box with a glass sphere in place of the tall block,",
            "# written by make_scene.py (also as scene.json for Mitsuba).", "",
            "background = [0, 0, 0]", "", "[camera]"]
    toml += ["%s = %s" % (k, json.dumps(camera[k])) for k in ("position", "look_at", "up", "fov_y_deg")]
    toml += ["", "[render]", "resolution = %s" % json.dumps(list(RESOLUTION)), 'integrator = "path"',
             "max_depth = 16", "spp = 256", ""]
    mats = [("white", WHITE), ("red", WALLS[3][1]), ("green", WALLS[4][1])]
    for n, a in mats:
        toml += ["[[materials]]", 'name = "%s"' % n, 'type = "lambert"', "albedo = %s" % json.dumps(a), ""]
    toml += ["[[materials]]", 'name = "light"', 'type = "lambert"', "albedo = 0",
             "emission = %s" % json.dumps(LIGHT), "", "[[materials]]", 'name = "glass"',
             'type = "dielectric"', "ior = 1.5", 'fresnel = "exact"', ""]
    colour = {"redwall": "red", "greenwall": "green"}
    for n, _ in WALLS + [("light", None), ("sphere", None)]:
        m = colour.get(n, "light" if n == "light" else "glass" if n == "sphere" else "white")
        toml += ["[[objects]]", 'name = "%s"' % n, 'mesh = "%s.obj"' % n, 'material = "%s"' % m, ""]
    with open(os.path.join(HERE, "scene.toml"), "w") as o:
        o.write("\n".join(toml))


main()
