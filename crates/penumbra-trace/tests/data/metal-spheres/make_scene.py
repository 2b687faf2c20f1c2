#!/usr/bin/env python3
"""Writes issue 13's metal scene: four spheres over a floor, in front of a
wall, lit by an emissive quad above them. From left to right: smooth glass
(ior 1.5), smooth gold, an ideal mirror and rough copper (GGX, alpha 0.2).
Writes the meshes (OBJ, world space), scene.json (the neutral format of
../shared/anchors, for Mitsuba) and scene.toml (penumbra).

Gold and copper take penumbra's presets (Johnson & Christy 1972), written
out as n and k in both files. The anchors' `roughconductor` takes alpha
itself, penumbra's `roughness` is sqrt(alpha). Mitsuba's rough conductor
uses the separable Smith G1(wo) G1(wi), penumbra the height-correlated G2:
they differ at grazing angles only (see README.md for the measured bias).

The reference image is rendered once with ../shared/anchors (README.md in
this folder); tests read it, they never run Mitsuba."""
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # ../icosphere.py
from icosphere import icosphere  # noqa: E402

RADIUS = 0.5
LEVELS = 3  # 20 · 4³ = 1280 triangles a sphere
RESOLUTION = (384, 256)
FLOOR = [0.7, 0.7, 0.7]
WALL = [0.5, 0.5, 0.5]
LIGHT = [12.0, 12.0, 12.0]
GOLD = ([0.14, 0.43, 1.38], [3.697, 2.455, 1.914])
COPPER = ([0.22, 1.02, 1.24], [3.747, 2.577, 2.397])
COPPER_ALPHA = 0.2
# name, x of the centre (the camera looks along +z: +x is on the left), the anchors' material, penumbra's material
SPHERES = [
    ("glass", 1.65, {"type": "dielectric", "ior": 1.5},
     ['type = "dielectric"', "ior = 1.5", 'fresnel = "exact"']),
    ("gold", 0.55, {"type": "conductor", "eta": GOLD[0], "k": GOLD[1]},
     ['type = "conductor"', "eta = %s" % json.dumps(GOLD[0]), "k = %s" % json.dumps(GOLD[1])]),
    ("mirror", -0.55, {"type": "mirror"}, ['type = "mirror"', "reflectance = 1"]),
    ("copper", -1.65, {"type": "roughconductor", "alpha": COPPER_ALPHA, "eta": COPPER[0], "k": COPPER[1]},
     ['type = "conductor"', "eta = %s" % json.dumps(COPPER[0]), "k = %s" % json.dumps(COPPER[1]),
      "roughness = %.7f" % math.sqrt(COPPER_ALPHA)]),
]
# Quads as two triangles, counter-clockwise seen from the front.
QUADS = {
    "floor": [(-4, 0, -3), (-4, 0, 3), (4, 0, 3), (4, 0, -3)],
    "wall": [(-4, 0, 2), (-4, 4, 2), (4, 4, 2), (4, 0, 2)],
    # The light faces down (front = counter-clockwise from below).
    "light": [(-0.75, 3, -0.25), (0.75, 3, -0.25), (0.75, 3, 1.25), (-0.75, 3, 1.25)],
}


def normal(q):
    e1 = [b - a for a, b in zip(q[0], q[1])]
    e2 = [b - a for a, b in zip(q[0], q[2])]
    return (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])


def main():
    for name, q in QUADS.items():
        with open(os.path.join(HERE, name + ".obj"), "w") as o:
            for p in q:
                o.write("v %.6f %.6f %.6f\n" % p)
            o.write("f 1 2 3\nf 1 3 4\n")
    assert normal(QUADS["floor"])[1] > 0 and normal(QUADS["light"])[1] < 0
    assert normal(QUADS["wall"])[2] < 0
    v, f = icosphere(LEVELS)
    for name, x, _, _ in SPHERES:
        centre = (x, RADIUS + 1e-3, 0.5)  # 1 mm above the floor: no coplanar contact
        with open(os.path.join(HERE, "sphere_%s.obj" % name), "w") as o:
            o.write("# %s sphere: icosphere, %d triangles, outward winding and normals\n" % (name, len(f)))
            for p in v:
                o.write("v %.6f %.6f %.6f\n" % tuple(c + RADIUS * u for c, u in zip(centre, p)))
            for p in v:
                o.write("vn %.6f %.6f %.6f\n" % p)
            for a, b, c in f:
                o.write("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1))
    camera = {"position": [0, 1.6, -4.2], "look_at": [0, 0.55, 0.5], "up": [0, 1, 0], "fov_y_deg": 30.0}
    objects = [{"name": n, "mesh": n + ".obj", "albedo": a, "emission": [0, 0, 0], "smooth": False}
               for n, a in (("floor", FLOOR), ("wall", WALL))]
    objects.append({"name": "light", "mesh": "light.obj", "albedo": [0, 0, 0], "emission": LIGHT,
                    "smooth": False})
    for name, _, material, _ in SPHERES:
        objects.append({"name": name, "mesh": "sphere_%s.obj" % name, "albedo": [0, 0, 0],
                        "emission": [0, 0, 0], "smooth": True, "material": material})
    scene = {"name": "metal-spheres", "units": "m", "camera": dict(camera, resolution=list(RESOLUTION)),
             "lights": [], "background": [0, 0, 0], "objects": objects}
    with open(os.path.join(HERE, "scene.json"), "w") as o:
        json.dump(scene, o, indent=1)
        o.write("\n")
    toml = ["# Issue 13's metal scene: glass, gold, mirror and rough copper spheres",
            "# over a floor, written by make_scene.py (also as scene.json for Mitsuba).", "",
            "background = [0, 0, 0]", "", "[camera]"]
    toml += ["%s = %s" % (k, json.dumps(camera[k])) for k in ("position", "look_at", "up", "fov_y_deg")]
    toml += ["", "[render]", "resolution = %s" % json.dumps(list(RESOLUTION)), 'integrator = "path"',
             "max_depth = 16", "spp = 256", ""]
    for n, a in (("floor", FLOOR), ("wall", WALL)):
        toml += ["[[materials]]", 'name = "%s"' % n, 'type = "lambert"', "albedo = %s" % json.dumps(a), ""]
    toml += ["[[materials]]", 'name = "light"', 'type = "lambert"', "albedo = 0",
             "emission = %s" % json.dumps(LIGHT), ""]
    for name, _, _, lines in SPHERES:
        toml += ["[[materials]]", 'name = "%s"' % name] + lines + [""]
    for n in ("floor", "wall", "light"):
        toml += ["[[objects]]", 'name = "%s"' % n, 'mesh = "%s.obj"' % n, 'material = "%s"' % n, ""]
    for name, _, _, _ in SPHERES:
        toml += ["[[objects]]", 'name = "%s"' % name, 'mesh = "sphere_%s.obj"' % name,
                 'material = "%s"' % name, ""]
    with open(os.path.join(HERE, "scene.toml"), "w") as o:
        o.write("\n".join(toml))


main()
