#!/usr/bin/env python3
"""Writes the bad-input corpus (bad/) and the odd-but-valid corpus (good/).

The files are committed; this script documents how each was made and rewrites them
(`python3 tests/corpus/make.py`). What each must give is in expected.json, which is kept by
hand: every bad file maps to a substring of its error (and, in "python_exception", to the
tessella exception class the Python package raises for it), every good file to its counts.
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
BAD = os.path.join(HERE, "bad")
GOOD = os.path.join(HERE, "good")

TRI_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"


def write(folder, name, data):
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def ply_header(fmt, nv, nf, vprops=("float x", "float y", "float z"), flist="uchar int"):
    lines = ["ply", f"format {fmt} 1.0", f"element vertex {nv}"]
    lines += [f"property {p}" for p in vprops]
    lines += [f"element face {nf}", f"property list {flist} vertex_indices", "end_header"]
    return ("\n".join(lines) + "\n").encode()


def ply_binary(verts, faces, vprops=("float x", "float y", "float z"), vfmt="<3f", nv=None, nf=None):
    body = b"".join(struct.pack(vfmt, *v) for v in verts)
    for f in faces:
        body += struct.pack("<B", len(f)) + struct.pack(f"<{len(f)}i", *f)
    header = ply_header("binary_little_endian", len(verts) if nv is None else nv,
                        len(faces) if nf is None else nf, vprops)
    return header + body


def ply_ascii(verts, faces, vprops=("float x", "float y", "float z")):
    body = "".join(" ".join(str(c) for c in v) + "\n" for v in verts)
    body += "".join(f"{len(f)} " + " ".join(str(i) for i in f) + "\n" for f in faces)
    return ply_header("ascii", len(verts), len(faces), vprops) + body.encode()


TRI = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def stl_binary(facets, count=None, header=b"tessella corpus"):
    out = header.ljust(80, b" ")[:80]
    out += struct.pack("<I", len(facets) if count is None else count)
    for f in facets:
        out += struct.pack("<3f", 0, 0, 1)
        for v in f:
            out += struct.pack("<3f", *v)
        out += b"\0\0"
    return out


def gltf_doc(positions, indices=None, mode=None, extra_bytes=0, index_count=None,
             position_count=None, uri=None, normals=None):
    """A one-primitive glTF; the buffer is embedded unless `uri` names another."""
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    data = pos
    accessors = [{"bufferView": 0, "componentType": 5126, "type": "VEC3",
                  "count": len(positions) if position_count is None else position_count,
                  "min": [0, 0, 0], "max": [1, 1, 0]}]
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)}]
    attributes = {"POSITION": 0}
    if normals is not None:
        nb = b"".join(struct.pack("<3f", *n) for n in normals)
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(nb)})
        accessors.append({"bufferView": len(views) - 1, "componentType": 5126, "type": "VEC3",
                          "count": len(normals)})
        attributes["NORMAL"] = len(accessors) - 1
        data += nb
    primitive = {"attributes": attributes}
    if indices is not None:
        ib = b"".join(struct.pack("<I", i) for i in indices)
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(ib)})
        accessors.append({"bufferView": len(views) - 1, "componentType": 5125, "type": "SCALAR",
                          "count": len(indices) if index_count is None else index_count})
        primitive["indices"] = len(accessors) - 1
        data += ib
    if mode is not None:
        primitive["mode"] = mode
    data += b"\0" * extra_bytes
    buffer = {"byteLength": len(data)}
    buffer["uri"] = uri if uri is not None else (
        "data:application/octet-stream;base64," + base64.b64encode(data).decode())
    return {"asset": {"version": "2.0"}, "buffers": [buffer], "bufferViews": views,
            "accessors": accessors, "meshes": [{"primitives": [primitive]}],
            "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}, data


def glb(doc, data):
    doc = dict(doc)
    doc["buffers"] = [{"byteLength": len(data)}]
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    data = data + b"\0" * (-len(data) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(data), b"BIN\0") + data
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def main():
    # ---------------------------------------------------------------- OBJ
    write(BAD, "obj-empty.obj", "")
    write(BAD, "obj-garbage.obj", bytes(range(256)) * 4)
    write(BAD, "obj-truncated-number.obj", TRI_OBJ + "v 0 1")
    write(BAD, "obj-bad-number.obj", "v 0 zero 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    write(BAD, "obj-index-out-of-range.obj", TRI_OBJ + "f 1 2 9\n")
    write(BAD, "obj-negative-index-out-of-range.obj", TRI_OBJ + "f -1 -2 -9\n")
    write(BAD, "obj-zero-index.obj", TRI_OBJ + "f 0 1 2\n")
    write(BAD, "obj-nan-position.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    write(BAD, "obj-inf-position.obj", "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    write(BAD, "obj-nan-normal.obj", TRI_OBJ + "vn nan 0 1\nf 1//1 2//1 3//1\n")
    write(BAD, "obj-zero-normal.obj", TRI_OBJ + "vn 0 0 0\nf 1//1 2//1 3//1\n")
    write(BAD, "obj-two-vertex-face.obj", TRI_OBJ + "f 1 2\n")
    write(BAD, "obj-degenerate-only.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    write(BAD, "obj-mixed-normals.obj",
          TRI_OBJ + "v 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n")
    write(BAD, "mesh.fbx", TRI_OBJ + "f 1 2 3\n")
    # ---------------------------------------------------------------- PLY
    tri_face = [[0, 1, 2]]
    write(BAD, "ply-empty.ply", "")
    write(BAD, "ply-garbage.ply", b"ply\n" + bytes(range(256)) * 4)
    write(BAD, "ply-bad-format.ply", "ply\nformat utf16 1.0\nend_header\n")
    write(BAD, "ply-no-end-header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n")
    write(BAD, "ply-truncated-ascii.ply", ply_ascii(TRI, tri_face)[:-6])
    write(BAD, "ply-truncated-binary.ply", ply_binary(TRI, tri_face)[:-7])
    write(BAD, "ply-huge-vertex-count.ply", ply_binary(TRI, tri_face, nv=4_000_000_000))
    write(BAD, "ply-huge-face-count.ply", ply_binary(TRI, tri_face, nf=2_000_000_000))
    write(BAD, "ply-index-out-of-range.ply", ply_ascii(TRI, [[0, 1, 7]]))
    write(BAD, "ply-negative-index.ply", ply_binary(TRI, [[0, 1, -1]]))
    write(BAD, "ply-two-vertex-face.ply", ply_ascii(TRI, [[0, 1]]))
    nan = float("nan")
    write(BAD, "ply-nan-position.ply", ply_binary([(nan, 0, 0)] + TRI[1:], tri_face))
    write(BAD, "ply-inf-position.ply", ply_binary([(float("inf"), 0, 0)] + TRI[1:], tri_face))
    nprops = ("float x", "float y", "float z", "float nx", "float ny", "float nz")
    write(BAD, "ply-inf-normal.ply",
          ply_binary([p + (0, 0, float("-inf")) for p in TRI], tri_face, nprops, "<6f"))
    write(BAD, "ply-zero-normal.ply",
          ply_binary([p + (0, 0, 0) for p in TRI], tri_face, nprops, "<6f"))
    write(BAD, "ply-huge-list-count.ply",
          ply_header("binary_little_endian", 3, 1) + b"".join(struct.pack("<3f", *v) for v in TRI)
          + struct.pack("<B", 255) + struct.pack("<3i", 0, 1, 2))
    # ---------------------------------------------------------------- glTF / GLB
    doc, data = gltf_doc(TRI, [0, 1, 2])
    text = json.dumps(doc)
    write(BAD, "gltf-empty.gltf", "")
    write(BAD, "gltf-truncated.gltf", text[: len(text) // 2])
    write(BAD, "gltf-garbage.gltf", bytes(range(256)) * 4)
    doc2, _ = gltf_doc(TRI, [0, 1, 2], position_count=30)
    write(BAD, "gltf-accessor-beyond-buffer.gltf", json.dumps(doc2))
    doc3, _ = gltf_doc(TRI, [0, 1, 2])
    doc3["bufferViews"][0]["byteLength"] = 4096
    write(BAD, "gltf-buffer-view-beyond-buffer.gltf", json.dumps(doc3))
    doc4, _ = gltf_doc(TRI, [0, 1, 2], uri="missing.bin")
    write(BAD, "gltf-missing-buffer-file.gltf", json.dumps(doc4))
    doc5, _ = gltf_doc(TRI, [0, 1, 2])
    doc5["buffers"][0]["uri"] = "data:application/octet-stream;base64,@@not base64@@"
    write(BAD, "gltf-bad-base64.gltf", json.dumps(doc5))
    write(BAD, "gltf-points-mode.gltf", json.dumps(gltf_doc(TRI, [0, 1, 2], mode=0)[0]))
    write(BAD, "gltf-lines-mode.gltf", json.dumps(gltf_doc(TRI, [0, 1, 1, 2], mode=1)[0]))
    write(BAD, "gltf-index-out-of-range.gltf", json.dumps(gltf_doc(TRI, [0, 1, 5])[0]))
    write(BAD, "gltf-nan-position.gltf",
          json.dumps(gltf_doc([(nan, 0, 0)] + TRI[1:], [0, 1, 2])[0]))
    write(BAD, "gltf-zero-normal.gltf",
          json.dumps(gltf_doc(TRI, [0, 1, 2], normals=[(0, 0, 0)] * 3)[0]))
    write(BAD, "gltf-two-indices.gltf", json.dumps(gltf_doc(TRI, [0, 1])[0]))
    doc6, _ = gltf_doc(TRI, [0, 1, 2])
    del doc6["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
    doc6["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 0
    write(BAD, "gltf-no-position.gltf", json.dumps(doc6))
    good_glb = glb(*gltf_doc(TRI, [0, 1, 2]))
    write(BAD, "glb-empty.glb", "")
    write(BAD, "glb-bad-magic.glb", b"gLTf" + good_glb[4:])
    write(BAD, "glb-truncated.glb", good_glb[: len(good_glb) - 20])
    bad_chunk = bytearray(good_glb)
    bad_chunk[12:16] = struct.pack("<I", 1_000_000)
    write(BAD, "glb-bad-json-chunk-length.glb", bytes(bad_chunk))
    bad_total = bytearray(good_glb)
    bad_total[8:12] = struct.pack("<I", 7)
    write(BAD, "glb-bad-total-length.glb", bytes(bad_total))
    # ---------------------------------------------------------------- STL
    write(BAD, "stl-empty.stl", "")
    write(BAD, "stl-garbage.stl", bytes(range(256)) * 4)
    write(BAD, "stl-truncated-binary.stl", stl_binary([TRI], count=10))
    write(BAD, "stl-huge-count.stl", stl_binary([TRI], count=0xFFFFFFFF))
    write(BAD, "stl-truncated-ascii.stl",
          "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n")
    write(BAD, "stl-nan-vertex.stl", stl_binary([[(nan, 0, 0)] + TRI[1:]]))
    write(BAD, "stl-degenerate-only.stl", stl_binary([[(0, 0, 0), (1, 0, 0), (2, 0, 0)]]))

    # ---------------------------------------------------------------- good
    quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    write(GOOD, "obj-crlf.obj", (quad + "f 1 2 3\nf 1 3 4\n").replace("\n", "\r\n"))
    write(GOOD, "obj-polygons.obj",
          quad + "v 2 0 0\nv 2 1 0\nv 1.5 2 0\nf 1 2 3 4\nf 2 5 6 7 3\n")
    write(GOOD, "obj-missing-mtllib.obj",
          "mtllib does-not-exist.mtl\n" + quad + "usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\n")
    write(GOOD, "obj-comments-negative-indices.obj",
          "# exported\n\n" + quad + "o patch\ns off\nf -4 -3 -2\nf -4 -2 -1\n")
    write(GOOD, "ply-double.ply",
          ply_header("binary_little_endian", 3, 1, ("double x", "double y", "double z"))
          + b"".join(struct.pack("<3d", *v) for v in TRI) + struct.pack("<B3i", 3, 0, 1, 2))
    write(GOOD, "ply-crlf-ascii.ply", ply_ascii(TRI, tri_face).replace(b"\n", b"\r\n"))
    write(GOOD, "ply-big-endian.ply",
          ply_header("binary_big_endian", 3, 1) + b"".join(struct.pack(">3f", *v) for v in TRI)
          + struct.pack(">B3i", 3, 0, 1, 2))
    write(GOOD, "stl-solid-header.stl",
          stl_binary([TRI, [(1, 0, 0), (1, 1, 0), (0, 1, 0)]], header=b"solid exported by CAD"))
    write(GOOD, "stl-ascii-no-name.stl",
          "solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
          "endloop\nendfacet\nendsolid\n")
    doc7, data7 = gltf_doc(TRI, [0, 1, 2], uri="buffer%20data.bin")
    write(GOOD, "gltf-external-buffer.gltf", json.dumps(doc7))
    write(GOOD, "buffer data.bin", data7)
    write(GOOD, "glb-triangle.glb", good_glb)


if __name__ == "__main__":
    main()
