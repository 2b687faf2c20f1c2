#!/usr/bin/env python3
"""Writes a textured glTF binary for load and texture-cost benchmarks.

    python3 scripts/textured_bench_gltf.py OUT.glb [--triangles N] [--texture PX]

A wavy height field of about N triangles (default 1,000,000) with NORMAL
and TEXCOORD_0, one metallic-roughness material with a base-colour, a
metallic-roughness and a normal texture (PX x PX PNGs, default 2048),
and a camera looking at it from above at an angle. No lights: `penumbra
render` lights it with its studio environment. Standard library only.
"""

import argparse
import json
import math
import struct
import sys
import zlib
from array import array


def png(width, height, pixel):
    """An 8-bit RGB PNG of pixel(x, y) -> (r, g, b) bytes."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)
        for x in range(width):
            rows.extend(pixel(x, y))

    def chunk(kind, data):
        c = kind + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(bytes(rows), 6))
        + chunk(b"IEND", b"")
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--texture", type=int, default=2048)
    a = ap.parse_args()
    n = max(1, int(math.sqrt(a.triangles / 2)))  # quads per side
    positions, normals, uvs = array("f"), array("f"), array("f")
    for j in range(n + 1):
        for i in range(n + 1):
            u, v = i / n, j / n
            x, z = 2 * u - 1, 2 * v - 1
            y = 0.05 * math.sin(12 * x) * math.cos(9 * z)
            dx = 0.05 * 12 * math.cos(12 * x) * math.cos(9 * z)
            dz = -0.05 * 9 * math.sin(12 * x) * math.sin(9 * z)
            ln = math.sqrt(dx * dx + 1 + dz * dz)
            positions.extend((x, y, z))
            normals.extend((-dx / ln, 1 / ln, -dz / ln))
            uvs.extend((4 * u, 4 * v))
    indices = array("I")
    for j in range(n):
        for i in range(n):
            k = j * (n + 1) + i
            indices.extend((k, k + n + 1, k + 1, k + 1, k + n + 1, k + n + 2))
    t = a.texture
    images = [
        png(t, t, lambda x, y: bytes(((x * 7) & 255, (y * 5) & 255, ((x ^ y) * 3) & 255))),
        # Roughness (G) in [64, 191], metallic (B) in bands of 16 rows.
        png(t, t, lambda x, y: bytes((0, 64 + (x * 3 & 127), 255 * ((y >> 4) & 1)))),
        png(t, t, lambda x, y: bytes((128 + int(60 * math.sin(x / 9)), 128 + int(60 * math.sin(y / 7)), 230))),
    ]
    blobs = [positions.tobytes(), normals.tobytes(), uvs.tobytes(), indices.tobytes()] + images
    views, offset, buf = [], 0, bytearray()
    for b in blobs:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b)})
        buf.extend(b)
        buf.extend(b"\0" * (-len(buf) % 4))
        offset = len(buf)
    count = (n + 1) ** 2
    gltf = {
        "asset": {"version": "2.0", "generator": "penumbra scripts/textured_bench_gltf.py"},
        "buffers": [{"byteLength": len(buf)}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
             "min": [-1, -0.05, -1], "max": [1, 0.05, 1]},
            {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": count, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
        ],
        "images": [{"bufferView": 4 + k, "mimeType": "image/png"} for k in range(3)],
        "samplers": [{}],
        "textures": [{"source": k, "sampler": 0} for k in range(3)],
        "materials": [{
            "name": "textured",
            "pbrMetallicRoughness": {
                "baseColorTexture": {"index": 0},
                "metallicRoughnessTexture": {"index": 1},
            },
            "normalTexture": {"index": 2},
        }],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0, 1.6, 1.6],
             "rotation": [-0.3826834, 0, 0, 0.9238795]},
        ],
        "scenes": [{"nodes": [0, 1]}],
        "scene": 0,
    }
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    with open(a.out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(buf)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(buf), 0x004E4942) + bytes(buf))
    print(f"wrote {a.out}: {len(indices) // 3} triangles, three {t}x{t} textures", file=sys.stderr)


if __name__ == "__main__":
    main()
