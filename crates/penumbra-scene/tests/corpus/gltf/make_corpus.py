#!/usr/bin/env python3
"""Regenerates the glTF test corpus (bad and good files) in this folder.

Run from anywhere: python3 make_corpus.py. Each file exercises one loader
check; tests/gltf_corpus.rs has one test per file.
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(HERE, name), mode) as f:
        f.write(data)


def data_uri(b):
    return "data:application/octet-stream;base64," + base64.b64encode(b).decode()


def f32s(vals):
    return struct.pack("<%df" % len(vals), *vals)


def pad4(b, fill=b"\0"):
    return b + fill * (-len(b) % 4)


TRI = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]


def triangle_doc(positions=TRI, indices=(0, 1, 2), uri=None, count=None, extra=None):
    """One indexed triangle: POSITION = accessors[0], indices = accessors[1]."""
    pos = f32s(positions)
    idx = pad4(struct.pack("<%dH" % len(indices), *indices))
    buf = pos + idx
    n = len(positions) // 3
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": uri if uri is not None else data_uri(buf), "byteLength": len(buf)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": 2 * len(indices)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": count if count is not None else n,
             "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
    }
    if extra:
        doc.update(extra)
    return doc, buf


def dump(doc):
    return json.dumps(doc, indent=1) + "\n"


def glb(doc, bin_chunk):
    j = pad4(json.dumps(doc).encode(), b" ")
    b = pad4(bin_chunk)
    total = 12 + 8 + len(j) + 8 + len(b)
    return (b"glTF" + struct.pack("<II", 2, total)
            + struct.pack("<I", len(j)) + b"JSON" + j
            + struct.pack("<I", len(b)) + b"BIN\0" + b)


# --- bad files -------------------------------------------------------------
write("empty.gltf", b"")

doc, buf = triangle_doc()
del doc["buffers"][0]["uri"]
good_glb = glb(doc, buf)
write("ok_triangle.glb", good_glb)
write("truncated.glb", good_glb[: len(good_glb) - 20])

text = dump(triangle_doc()[0])
write("truncated_json.gltf", text[: len(text) // 2])

write("missing_bin.gltf", dump(triangle_doc(uri="missing.bin")[0]))

# 3 vertices of data, but the accessor claims 4.
write("accessor_past_end.gltf", dump(triangle_doc(count=4)[0]))

doc, _ = triangle_doc()
doc["bufferViews"][0]["byteLength"] = 400  # buffer has 44 bytes
write("view_past_buffer.gltf", dump(doc))

nan = TRI[:]
nan[3] = float("nan")
write("nan_position.gltf", dump(triangle_doc(positions=nan)[0]))

write("index_out_of_range.gltf", dump(triangle_doc(indices=(0, 1, 7))[0]))

doc, _ = triangle_doc()
doc["asset"]["version"] = "3.0"
write("version3.gltf", dump(doc))

write("uri_parent.gltf", dump(triangle_doc(uri="../outside.bin")[0]))
write("uri_absolute.gltf", dump(triangle_doc(uri="/etc/passwd")[0]))

doc, buf = triangle_doc(uri="short.bin")
write("short.bin", buf[:20])
write("short_bin.gltf", dump(doc))

doc, _ = triangle_doc()
doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99
write("position_accessor_missing.gltf", dump(doc))

doc, _ = triangle_doc()
doc["nodes"] = [{"children": [1]}, {"mesh": 0, "children": [0]}]
write("node_cycle.gltf", dump(doc))

doc, _ = triangle_doc()
doc["buffers"][0]["uri"] = "data:application/octet-stream;base64,AAA*"
write("bad_base64.gltf", dump(doc))

doc, _ = triangle_doc(extra={"extensionsUsed": ["KHR_draco_mesh_compression"],
                             "extensionsRequired": ["KHR_draco_mesh_compression"]})
write("required_draco.gltf", dump(doc))

# --- files that load, with warnings ------------------------------------------
# Three triangles: one good, one with a repeated vertex, one collinear.
quad = [0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0]
write("degenerate.gltf", dump(triangle_doc(positions=quad, indices=(0, 1, 2, 0, 1, 1, 0, 1, 3))[0]))


def png_2x1():
    """A 2x1 RGB PNG: (255, 128, 0), (0, 0, 255)."""
    import zlib
    raw = b"\0" + bytes([255, 128, 0, 0, 0, 255])
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 1, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


# A feature file: instancing through a hierarchy, TEXCOORD_0, NORMAL, a
# non-indexed primitive, a LINES primitive (skipped), materials, a texture,
# a spot light and a camera with an aspect ratio.
pos = f32s(TRI)
nrm = f32s([0, 0, 1] * 3)
uv = f32s([0, 0, 1, 0, 0, 1])
idx = pad4(struct.pack("<3H", 0, 1, 2))
buf = pos + nrm + uv + idx
o_n, o_uv, o_idx = len(pos), len(pos) + len(nrm), len(pos) + len(nrm) + len(uv)
doc = {
    "asset": {"version": "2.0", "generator": "make_corpus.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength",
                       "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_animation_pointer"],
    "scene": 0,
    "scenes": [{"nodes": [0, 3, 4]}],
    "nodes": [
        {"name": "parent", "translation": [10, 0, 0], "scale": [2, 2, 2], "children": [1, 2]},
        {"name": "a", "mesh": 0},
        {"name": "b", "mesh": 0, "rotation": [0, 0, 0.7071067811865476, 0.7071067811865476]},
        {"name": "cam", "camera": 0, "translation": [0, 0, 5]},
        {"name": "spot", "translation": [0, 3, 0],
         "rotation": [-0.7071067811865476, 0, 0, 0.7071067811865476],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
    ],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1}}],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "spot", "color": [1, 0.5, 0.25], "intensity": 683, "range": 10,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.4}}]}},
    "meshes": [{"name": "tri", "primitives": [
        {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0},
        {"attributes": {"POSITION": 0}, "material": 1},
        {"attributes": {"POSITION": 0}, "indices": 3, "mode": 1},
    ]}],
    "materials": [
        {"name": "textured", "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 1,
            "baseColorTexture": {"index": 0}},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0}}},
        {"name": "shiny", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0.5,
                                  "roughnessFactor": 0.3},
         "normalTexture": {"index": 0},
         "emissiveFactor": [1, 1, 1],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4},
                        "KHR_materials_clearcoat": {"clearcoatFactor": 1}}},
    ],
    "textures": [{"source": 0}],
    "images": [{"uri": "data:image/png;base64," + base64.b64encode(png_2x1()).decode()}],
    "buffers": [{"uri": data_uri(buf), "byteLength": len(buf)}],
    "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
        {"buffer": 0, "byteOffset": o_n, "byteLength": len(nrm)},
        {"buffer": 0, "byteOffset": o_uv, "byteLength": len(uv)},
        {"buffer": 0, "byteOffset": o_idx, "byteLength": 6},
    ],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"},
    ],
}
write("ok_features.gltf", dump(doc))

# Sparse accessors: POSITION = dense data with vertex 2 replaced by (0, 5, 0);
# NORMAL has no bufferView (zeros) with all three set to +z sparsely.
pos = f32s(TRI)
idx = pad4(struct.pack("<3H", 0, 1, 2))
sp_idx = pad4(struct.pack("<B", 2))
sp_val = f32s([0, 5, 0])
n_idx = pad4(struct.pack("<3H", 0, 1, 2))
n_val = f32s([0, 0, 1] * 3)
parts = [pos, idx, sp_idx, sp_val, n_idx, n_val]
offsets = [sum(len(p) for p in parts[:i]) for i in range(len(parts))]
buf = b"".join(parts)
doc = {
    "asset": {"version": "2.0"},
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 2}, "indices": 1}]}],
    "buffers": [{"uri": data_uri(buf), "byteLength": len(buf)}],
    "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": len(p)} for o, p in zip(offsets, parts)],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 5, 0],
         "sparse": {"count": 1, "indices": {"bufferView": 2, "componentType": 5121},
                    "values": {"bufferView": 3}}},
        {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        {"componentType": 5126, "count": 3, "type": "VEC3",
         "sparse": {"count": 3, "indices": {"bufferView": 4, "componentType": 5123},
                    "values": {"bufferView": 5}}},
    ],
}
write("ok_sparse.gltf", dump(doc))
# The same with a sparse index out of range.
doc["accessors"][0]["sparse"]["indices"]["byteOffset"] = 0
bad = b"".join([pos, idx, pad4(struct.pack("<B", 9)), sp_val, n_idx, n_val])
doc["buffers"][0]["uri"] = data_uri(bad)
write("sparse_index_out_of_range.gltf", dump(doc))

# A texture whose image file does not exist.
doc, _ = triangle_doc(extra={
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}],
    "images": [{"uri": "no_such_image.png"}],
})
doc["meshes"][0]["primitives"][0]["material"] = 0
write("missing_image.gltf", dump(doc))

# Material models: one primitive per material on the same triangle. Exact
# Lambert (ior 1), glass (KHR_materials_transmission + _ior), a textured
# metal (metallicRoughnessTexture, linear), KHR_materials_specular with
# textures (ignored, warned) and emissive strength, and glTF's defaults.
pos = f32s(TRI)
doc = {
    "asset": {"version": "2.0", "generator": "make_corpus.py"},
    "extensionsUsed": ["KHR_materials_ior", "KHR_materials_transmission",
                       "KHR_materials_specular", "KHR_materials_emissive_strength"],
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": m} for m in range(5)]}],
    "materials": [
        {"name": "matte", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.6, 0.5, 1],
                                                   "metallicFactor": 0},
         "extensions": {"KHR_materials_ior": {"ior": 1.0}}},
        {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0},
         "extensions": {"KHR_materials_ior": {"ior": 1.33},
                        "KHR_materials_transmission": {"transmissionFactor": 0.9}}},
        {"name": "metal", "pbrMetallicRoughness": {
            "baseColorFactor": [1, 0.8, 0.3, 1], "metallicFactor": 1, "roughnessFactor": 0.25,
            "metallicRoughnessTexture": {"index": 0}}},
        {"name": "coated", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 1],
                                                    "metallicFactor": 0, "roughnessFactor": 0.5},
         "emissiveFactor": [1, 0.5, 0],
         "extensions": {"KHR_materials_specular": {"specularFactor": 0.5,
                                                   "specularColorFactor": [1, 0.5, 0.25],
                                                   "specularTexture": {"index": 0}},
                        "KHR_materials_emissive_strength": {"emissiveStrength": 3}}},
        {"name": "defaults"},
    ],
    "textures": [{"source": 0}],
    "images": [{"uri": "data:image/png;base64," + base64.b64encode(png_2x1()).decode()}],
    "buffers": [{"uri": data_uri(pos), "byteLength": len(pos)}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}],
}
write("ok_materials.gltf", dump(doc))

# EXT_mesh_gpu_instancing: one triangle drawn three times under a node moved
# up by 10: instance 0 as is, 1 moved by x + 2, turned 90° about z and
# scaled 2, 2 moved by z - 3, turned 180° about y and squashed to y 0.5; the
# rotations as normalised signed shorts (KHR_mesh_quantization's encoding).
half = 2 ** -0.5
tr = f32s([0, 0, 0, 2, 0, 0, 0, 0, -3])
rot = struct.pack("<12h", *[round(v * 32767) for v in [0, 0, 0, 1, 0, 0, half, half, 0, 1, 0, 0]])
sc = f32s([1, 1, 1, 2, 2, 2, 1, 0.5, 1])
doc, buf = triangle_doc()
parts = [buf, tr, rot, sc]
offsets = [sum(len(p) for p in parts[:i]) for i in range(len(parts))]
doc["buffers"][0] = {"uri": data_uri(b"".join(parts)), "byteLength": sum(len(p) for p in parts)}
doc["bufferViews"] += [{"buffer": 0, "byteOffset": o, "byteLength": len(p)} for o, p in zip(offsets[1:], parts[1:])]
doc["accessors"] += [
    {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3"},
    {"bufferView": 3, "componentType": 5122, "normalized": True, "count": 3, "type": "VEC4"},
    {"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3"},
]
doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
doc["nodes"] = [{"mesh": 0, "translation": [0, 10, 0], "extensions": {"EXT_mesh_gpu_instancing": {
    "attributes": {"TRANSLATION": 2, "ROTATION": 3, "SCALE": 4}}}}]
write("ok_instancing.gltf", dump(doc))

# TEXCOORD_1: four unit-height quads (x in [-1, 1]) in rows one above the
# other, facing +z, whose TEXCOORD_0 is mirrored in u and TEXCOORD_1 is not,
# and a 2x1 RGBA image, black and transparent on the left, white and opaque
# on the right, clamped at the edges. Every material reads TEXCOORD_1, so
# each row is dark on the left and bright on the right; a renderer reading
# TEXCOORD_0 shows them mirrored. Rows from the top: base colour
# (texCoord 1), emission (texCoord 1), alpha MASK of the base colour's
# alpha (texCoord 1), base colour with texCoord 0 overridden to 1 by
# KHR_texture_transform's texCoord. Materials are exact Lambert (ior 1).
def png_2x1_rgba():
    """A 2x1 RGBA PNG: (0, 0, 0, 0), (255, 255, 255, 255)."""
    import zlib
    raw = b"\0" + bytes([0, 0, 0, 0, 255, 255, 255, 255])
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 1, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


pos = f32s([-1, 0, 0, 1, 0, 0, 1, 1, 0, -1, 1, 0])
nrm = f32s([0, 0, 1] * 4)
uv1 = f32s([0, 1, 1, 1, 1, 0, 0, 0])
uv0 = f32s([1, 1, 0, 1, 0, 0, 1, 0])
idx = pad4(struct.pack("<6H", 0, 1, 2, 0, 2, 3))
parts = [pos, nrm, uv0, uv1, idx]
offsets = [sum(len(p) for p in parts[:i]) for i in range(len(parts))]
ior1 = {"KHR_materials_ior": {"ior": 1.0}}
lambert = {"metallicFactor": 0}
doc = {
    "asset": {"version": "2.0", "generator": "make_corpus.py"},
    "extensionsUsed": ["KHR_materials_ior", "KHR_texture_transform"],
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3]}],
    "nodes": [{"mesh": m, "translation": [0, -1.25 * m, 0]} for m in range(4)],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2,
                                               "TEXCOORD_1": 3},
                                "indices": 4, "material": m}]} for m in range(4)],
    "materials": [
        {"name": "base colour on 1",
         "pbrMetallicRoughness": dict(lambert, baseColorTexture={"index": 0, "texCoord": 1}),
         "extensions": ior1},
        {"name": "emission on 1",
         "pbrMetallicRoughness": dict(lambert, baseColorFactor=[0, 0, 0, 1]),
         "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0, "texCoord": 1},
         "extensions": ior1},
        {"name": "mask on 1", "alphaMode": "MASK",
         "pbrMetallicRoughness": dict(lambert, baseColorTexture={"index": 0, "texCoord": 1}),
         "extensions": ior1},
        {"name": "override to 1",
         "pbrMetallicRoughness": dict(lambert, baseColorTexture={
             "index": 0, "texCoord": 0,
             "extensions": {"KHR_texture_transform": {"texCoord": 1}}}),
         "extensions": ior1},
    ],
    "samplers": [{"wrapS": 33071, "wrapT": 33071}],
    "textures": [{"source": 0, "sampler": 0}],
    "images": [{"uri": "data:image/png;base64," + base64.b64encode(png_2x1_rgba()).decode()}],
    "buffers": [{"uri": data_uri(b"".join(parts)), "byteLength": sum(len(p) for p in parts)}],
    "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": len(p)} for o, p in zip(offsets, parts)],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [-1, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ],
}
write("ok_texcoord1.gltf", dump(doc))
