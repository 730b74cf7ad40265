"""Writes the malformed FBX files of tests/data/malformed/ (their expected
errors are in EXPECTED.tsv there) from the small valid files in
tests/data/fbx/: each breaks one thing a reader must refuse with a located
error and never a crash, a hang or an unbounded allocation.

usage: python3 make_malformed_fbx.py   (writes into tests/data/malformed/)
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import fbx_convert as fc

HERE = Path(__file__).resolve().parent
DATA = HERE.parent / "data"
OUT = DATA / "malformed"


def encode_file(version, nodes, footer=b""):
    out = bytearray(fc.MAGIC + struct.pack("<I", version))
    fc.encode(nodes, version >= 7500, out)
    out += b"\0" * (25 if version >= 7500 else 13)
    return bytes(out + footer)


def find(nodes, *path):
    """The first node along the path of names, each a child of the last."""
    node = None
    for name in path:
        node = next(n for n in nodes if n.name == name)
        nodes = node.children
    return node


def objects(nodes, kind, cls):
    return [n for n in find(nodes, "Objects").children
            if n.name == kind and n.props[2][1] == cls.encode()]


def int_array(values):
    raw = struct.pack(f"<{len(values)}i", *values)
    stored = zlib.compress(raw)
    return ("i", values, b"i" + struct.pack("<III", len(values), 1, len(stored)) + stored)


def with_array(node, name, values):
    child = next(c for c in node.children if c.name == name)
    child.props = [int_array(values)]


def load(name):
    version, nodes, footer = fc.load(DATA / "fbx" / name)
    return version, nodes, footer


def write(name, data):
    (OUT / name).write_bytes(data)


def main():
    cube = (DATA / "fbx" / "cube.fbx").read_bytes()

    # The file cut in the middle: the Objects node ends past the file's end.
    write("fbx-truncated.fbx", cube[: len(cube) // 2])

    # A version this reader does not read.
    write("fbx-version-6100.fbx", cube[:23] + struct.pack("<I", 6100) + cube[27:])

    # A property whose type code is no type.
    version, nodes, footer = load("cube.fbx")
    creator = find(nodes, "Creator")
    creator.props = [("S", b"", b"Z" + creator.props[0][2][1:])]
    write("fbx-unknown-type.fbx", encode_file(version, nodes, footer))

    # A child whose record claims to end past its parent's end.
    data = bytearray(encode_file(version, load("cube.fbx")[1], footer))
    first = 27  # FBXHeaderExtension
    parent_end = struct.unpack_from("<I", data, first)[0]
    child = first + 13 + len("FBXHeaderExtension")
    struct.pack_into("<I", data, child, parent_end + 100)
    write("fbx-node-past-parent.fbx", bytes(data))

    # A deflated array whose header claims more elements than its stream
    # inflates to, and one claiming more than any stream of its size could.
    version, nodes, footer = load("cube.fbx")
    geometry = objects(nodes, "Geometry", "Mesh")[0]
    pvi = next(c for c in geometry.children if c.name == "PolygonVertexIndex")
    code, values, raw = pvi.props[0]
    _, encoding, stored = struct.unpack_from("<III", raw, 1)
    assert encoding == 1
    pvi.props = [(code, values, b"i" + struct.pack("<III", len(values) + 8, 1, stored) + raw[13:])]
    write("fbx-array-inflates-short.fbx", encode_file(version, nodes, footer))
    pvi.props = [(code, values, b"i" + struct.pack("<III", 0x40000000, 1, stored) + raw[13:])]
    write("fbx-array-claims-too-much.fbx", encode_file(version, nodes, footer))

    # A polygon corner naming a control point the geometry does not have.
    version, nodes, footer = load("cube.fbx")
    geometry = objects(nodes, "Geometry", "Mesh")[0]
    pvi = next(c for c in geometry.children if c.name == "PolygonVertexIndex")
    bad = list(pvi.props[0][1])
    bad[5] = 1000
    with_array(geometry, "PolygonVertexIndex", bad)
    write("fbx-polygon-index-out-of-range.fbx", encode_file(version, nodes, footer))

    # A UV index beyond the UV array.
    version, nodes, footer = load("cube.fbx")
    geometry = objects(nodes, "Geometry", "Mesh")[0]
    uv = next(c for c in geometry.children if c.name == "LayerElementUV")
    index = next(c for c in uv.children if c.name == "UVIndex")
    bad = list(index.props[0][1])
    bad[3] = 100000
    with_array(uv, "UVIndex", bad)
    write("fbx-uv-index-out-of-range.fbx", encode_file(version, nodes, footer))

    # A skin cluster naming a control point beyond the mesh.
    version, nodes, footer = load("strip.fbx")
    cluster = objects(nodes, "Deformer", "Cluster")[0]
    indexes = next(c for c in cluster.children if c.name == "Indexes")
    bad = list(indexes.props[0][1])
    bad[-1] = 21
    with_array(cluster, "Indexes", bad)
    write("fbx-cluster-index-out-of-range.fbx", encode_file(version, nodes, footer))

    # A model hierarchy with a cycle: the root bone made a child of its child.
    version, nodes, footer = load("strip.fbx")
    models = {n.props[1][1].split(b"\0")[0]: n.props[0][1]
              for n in find(nodes, "Objects").children if n.name == "Model"}
    connections = find(nodes, "Connections")
    link = fc.Node("C", [("S", b"OO", b"S" + struct.pack("<I", 2) + b"OO"),
                         ("L", models[b"Root"], b"L" + struct.pack("<q", models[b"Root"])),
                         ("L", models[b"Tip"], b"L" + struct.pack("<q", models[b"Tip"]))], [], False)
    connections.children.append(link)
    write("fbx-model-cycle.fbx", encode_file(version, nodes, footer))

    # Nodes nested 100 deep.
    deep = fc.Node("Leaf", [("I", 0, b"I" + struct.pack("<i", 0))], [], False)
    for _ in range(100):
        deep = fc.Node("Nest", [], [deep], True)
    write("fbx-nesting-bomb.fbx", encode_file(7400, [deep]))

    # ASCII: a scope never closed, and an array with fewer values than it says.
    text = (DATA / "fbx" / "strip-ascii.fbx").read_text()
    write("fbx-ascii-unclosed.fbx", text[: text.rindex("}")].encode())
    at = text.index("Vertices: *")
    count_end = text.index(" ", at + len("Vertices: *"))
    count = int(text[at + len("Vertices: *"):count_end])
    write("fbx-ascii-array-short.fbx",
          (text[:at] + f"Vertices: *{count + 3}" + text[count_end:]).encode())


if __name__ == "__main__":
    main()
