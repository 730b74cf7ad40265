"""The FBX exports (issue 47's inputs) are what they claim: binary FBX 7.4 or
later whose node tree walks cleanly and holds the skin clusters, blend
shape channels and animation stacks of its asset; and Assimp (the reader
the engine will use) reads them, where its command-line tool is installed."""

from __future__ import annotations

import re
import shutil
import struct
import subprocess
import zlib

import pytest

from rigged import assets_dir

MAGIC = b"Kaydara FBX Binary  \x00\x1a\x00"

# name: (skin clusters, blend shape channels, animation stacks)
EXPECTED = {
    "arm": (["UpperArm", "Forearm"], [], ["Wave"]),
    "arm-morph": (["UpperArm", "Forearm"], ["Flex"], ["Wave"]),
    "humanoid": (19, [], ["Hold", "Sway", "Walk"]),
    "prop": ([], [], []),
    "shapekey": ([], ["Bulge", "Pinch"], []),
}


class FbxNode:
    def __init__(self, name: str, properties: list, children: list):
        self.name, self.properties, self.children = name, properties, children


def read_properties(data: bytes, at: int, count: int) -> list:
    out = []
    for _ in range(count):
        code = chr(data[at])
        at += 1
        if code in "YCIFDL":
            size = {"Y": 2, "C": 1, "I": 4, "F": 4, "D": 8, "L": 8}[code]
            out.append(struct.unpack_from({"Y": "<h", "C": "<?", "I": "<i", "F": "<f", "D": "<d",
                                           "L": "<q"}[code], data, at)[0])
            at += size
        elif code in "SR":
            (length,) = struct.unpack_from("<I", data, at)
            raw = data[at + 4:at + 4 + length]
            out.append(raw.decode("utf-8", "replace") if code == "S" else raw)
            at += 4 + length
        elif code in "fdlib":
            length, encoding, stored = struct.unpack_from("<III", data, at)
            payload = data[at + 12:at + 12 + stored]
            expanded = zlib.decompress(payload) if encoding == 1 else payload
            width = {"f": 4, "d": 8, "l": 8, "i": 4, "b": 1}[code]
            assert len(expanded) == length * width, "array length disagrees with its bytes"
            out.append(("array", code, length))
            at += 12 + stored
        else:
            raise AssertionError(f"unknown FBX property type {code!r} at byte {at - 1}")
    return out


def read_nodes(data: bytes, at: int, end: int, wide: bool) -> tuple[list[FbxNode], int]:
    """The node records from at up to their null record (or end)."""
    head = "<QQQB" if wide else "<IIIB"
    head_size = struct.calcsize(head)
    nodes = []
    while at < end:
        node_end, count, list_length, name_length = struct.unpack_from(head, data, at)
        if node_end == 0:
            return nodes, at + head_size
        assert at < node_end <= len(data), f"node at byte {at} ends at {node_end}, past the file"
        name = data[at + head_size:at + head_size + name_length].decode("ascii")
        props_at = at + head_size + name_length
        properties = read_properties(data, props_at, count)
        children_at = props_at + list_length
        children, after = ([], children_at)
        if children_at < node_end:
            children, after = read_nodes(data, children_at, node_end, wide)
        assert after == node_end, f"node {name} at byte {at}: children end at {after}, " \
                                  f"not {node_end}"
        nodes.append(FbxNode(name, properties, children))
        at = node_end
    return nodes, at


def load_fbx(name: str) -> tuple[int, list[FbxNode]]:
    data = (assets_dir() / f"{name}.fbx").read_bytes()
    assert data[:len(MAGIC)] == MAGIC, f"{name}.fbx is not binary FBX"
    (version,) = struct.unpack_from("<I", data, len(MAGIC))
    nodes, _ = read_nodes(data, len(MAGIC) + 4, len(data), wide=version >= 7500)
    return version, nodes


def objects(nodes: list[FbxNode], kind: str, subtype: str) -> list[str]:
    """Names of the Objects' children of kind (Model, Deformer, Geometry,
    AnimationStack...) and subtype (their third property)."""
    found = []
    for section in (n for n in nodes if n.name == "Objects"):
        for obj in section.children:
            if obj.name == kind and (not subtype or obj.properties[2] == subtype):
                found.append(obj.properties[1].split("\x00\x01")[0])
    return found


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_fbx_is_binary_7_4_with_its_asset(name):
    version, nodes = load_fbx(name)
    print(f"\n{name}.fbx: FBX version {version}")
    assert version >= 7400
    top = [n.name for n in nodes]
    for section in ("FBXHeaderExtension", "Objects", "Connections"):
        assert section in top, f"{name}.fbx has no {section}"
    clusters, channels, stacks = EXPECTED[name]
    found_clusters = objects(nodes, "Deformer", "Cluster")
    if isinstance(clusters, int):
        assert len(found_clusters) == clusters
    else:
        assert sorted(found_clusters) == sorted(clusters)
    assert len(objects(nodes, "Deformer", "Skin")) == (1 if clusters else 0)
    assert sorted(objects(nodes, "Deformer", "BlendShapeChannel")) == sorted(channels)
    assert sorted(s.split("|")[-1] for s in objects(nodes, "AnimationStack", "")) == sorted(stacks)
    assert len(objects(nodes, "Geometry", "Mesh")) == 1


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_assimp_reads_fbx(name):
    assimp = shutil.which("assimp")
    if assimp is None:
        pytest.skip("the assimp command is not installed (Debian: assimp-utils)")
    path = assets_dir() / f"{name}.fbx"
    result = subprocess.run([assimp, "info", str(path)], capture_output=True, text=True,
                            timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr

    def count(label):
        match = re.search(rf"^{label}:\s+(\d+)", result.stdout, re.M)
        assert match, f"assimp info printed no {label}: {result.stdout}"
        return int(match.group(1))

    clusters, _, stacks = EXPECTED[name]
    assert count("Meshes") == 1
    assert count("Vertices") > 0
    assert count("Bones") == (clusters if isinstance(clusters, int) else len(clusters))
    assert count("Animations") == len(stacks)
