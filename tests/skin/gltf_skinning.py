"""An independent reference for glTF 2.0 skinning, in numpy.

Written from the glTF 2.0 specification (its sections on buffers, buffer
views and accessors, meshes and morph targets, skins, animations, and the
appendix on animation sampler interpolation), not from any of this project's
code, so that the engine's skinning can be checked against it. Float64
throughout; key times are the file's float32 values.

    asset = load("arm.glb")                     # .glb, or .gltf with its buffers
    animation_names(asset)                      # ["Wave"]
    posed_positions(asset, "Arm", "Wave", 0.5)  # (N, 3) posed world positions
    corrective(asset, "Arm", "Wave", 0.5, D)    # bind-space deltas of a posed edit D

A mesh is named by its node (index or name) or by the mesh's name (the first
node instancing it); times are seconds, clamped to the animation's range.
posed_positions returns one row per glTF vertex: every primitive of the mesh
in order, each primitive's vertices in file order. Morph targets are applied
before skinning, at the node's weights (node.weights, else mesh.weights, else
0) unless an animation's weights channel or morph_weights says otherwise;
extra_target adds one more morph target (an (N, 3) delta array) at weight 1.
"""

import base64
import json
import os
import struct

import numpy as np

_GLB_MAGIC = 0x46546C67  # "glTF"
_CHUNK_JSON = 0x4E4F534A
_CHUNK_BIN = 0x004E4942

COMPONENT_DTYPES = {
    5120: np.int8,
    5121: np.uint8,
    5122: np.int16,
    5123: np.uint16,
    5125: np.uint32,
    5126: np.float32,
}
_TYPE_SHAPES = {
    "SCALAR": (1,),
    "VEC2": (2,),
    "VEC3": (3,),
    "VEC4": (4,),
    "MAT2": (2, 2),
    "MAT3": (3, 3),
    "MAT4": (4, 4),
}


class Asset:
    """A parsed glTF: its JSON (gltf), its buffers' bytes and the nodes'
    parents."""

    def __init__(self, gltf, buffers):
        self.gltf = gltf
        self.buffers = buffers
        nodes = gltf.get("nodes", [])
        self.parent = [None] * len(nodes)
        for i, node in enumerate(nodes):
            for child in node.get("children", []):
                if self.parent[child] is not None:
                    raise ValueError(f"node {child} has two parents ({self.parent[child]} and {i})")
                self.parent[child] = i
        self._accessors = {}

    def accessor(self, index):
        """The accessor's elements as float64 (normalised integers mapped as
        the specification says), shape (count,) + element shape; cached."""
        if index not in self._accessors:
            self._accessors[index] = read_accessor(self, index)
        return self._accessors[index]

    def integer_accessor(self, index):
        """The accessor's elements as integers (indices, joints)."""
        return read_accessor(self, index, as_float=False)


def load(path):
    """Reads a .glb (header, JSON chunk, BIN chunk) or a .gltf whose buffers are
    data URIs or files beside it."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) >= 12 and struct.unpack_from("<I", data, 0)[0] == _GLB_MAGIC:
        gltf, bin_chunk = _parse_glb(data, path)
    else:
        gltf, bin_chunk = json.loads(data.decode("utf-8")), None
    buffers = []
    for i, buffer in enumerate(gltf.get("buffers", [])):
        uri = buffer.get("uri")
        if uri is None:
            if i != 0 or bin_chunk is None:
                raise ValueError(f"{path}: buffer {i} has no uri and is not the GLB's BIN chunk")
            blob = bin_chunk
        elif uri.startswith("data:"):
            blob = base64.b64decode(uri.split(",", 1)[1])
        else:
            with open(os.path.join(os.path.dirname(path), uri), "rb") as f:
                blob = f.read()
        if len(blob) < buffer["byteLength"]:
            raise ValueError(f"{path}: buffer {i} holds {len(blob)} bytes, "
                             f"byteLength says {buffer['byteLength']}")
        buffers.append(blob)
    return Asset(gltf, buffers)


def _parse_glb(data, path):
    magic, version, length = struct.unpack_from("<III", data, 0)
    if version != 2:
        raise ValueError(f"{path}: GLB version {version}, not 2")
    if length > len(data):
        raise ValueError(f"{path}: GLB length {length} past the file's {len(data)} bytes")
    at = 12
    gltf = bin_chunk = None
    while at < length:
        chunk_length, chunk_type = struct.unpack_from("<II", data, at)
        body = data[at + 8:at + 8 + chunk_length]
        if chunk_type == _CHUNK_JSON and gltf is None:
            gltf = json.loads(body.decode("utf-8"))
        elif chunk_type == _CHUNK_BIN and bin_chunk is None:
            bin_chunk = body
        at += 8 + chunk_length
    if gltf is None:
        raise ValueError(f"{path}: no JSON chunk")
    return gltf, bin_chunk


def _normalised(values, dtype):
    # The specification's normalised integers: signed types map to
    # max(c / (2^(n-1) - 1), -1), unsigned ones to c / (2^n - 1).
    if dtype == np.float32:
        return values.astype(np.float64)
    info = np.iinfo(dtype)
    scaled = values.astype(np.float64) / info.max
    return np.maximum(scaled, -1.0) if info.min < 0 else scaled


def _read_view(asset, view_index, byte_offset, count, dtype, shape):
    """count elements of shape from a buffer view, honouring byteStride and
    the 4-byte alignment of matrix columns."""
    gltf = asset.gltf
    view = gltf["bufferViews"][view_index]
    blob = asset.buffers[view["buffer"]]
    start = view.get("byteOffset", 0) + byte_offset
    if count == 0:
        return np.zeros((0,) + shape, dtype=dtype)
    itemsize = np.dtype(dtype).itemsize
    if len(shape) == 2:
        rows = shape[0]
        column_bytes = (rows * itemsize + 3) // 4 * 4
        element_bytes = column_bytes * shape[1]
    else:
        rows, column_bytes = shape[0], shape[0] * itemsize
        element_bytes = column_bytes
    stride = view.get("byteStride", element_bytes) or element_bytes
    end = start + (count - 1) * stride + element_bytes
    if end > view.get("byteOffset", 0) + view["byteLength"]:
        raise ValueError(f"accessor reads past the end of bufferView {view_index}")
    raw = np.frombuffer(blob, dtype=np.uint8, count=end - start, offset=start)
    columns = shape[1] if len(shape) == 2 else 1
    out = np.empty((count, columns, rows), dtype=dtype)
    for c in range(columns):
        for r in range(rows):
            offset = c * column_bytes + r * itemsize
            picked = np.lib.stride_tricks.as_strided(raw[offset:], shape=(count, itemsize),
                                                     strides=(stride, 1))
            out[:, c, r] = picked.copy().view(dtype).reshape(count)
    if len(shape) == 2:
        # Column-major in the file: element [row][column] is out[:, column, row].
        return out.transpose(0, 2, 1)
    return out.reshape((count,) + shape)


def read_accessor(asset, index, as_float=True):
    gltf = asset.gltf
    accessor = gltf["accessors"][index]
    dtype = COMPONENT_DTYPES[accessor["componentType"]]
    shape = _TYPE_SHAPES[accessor["type"]]
    count = accessor["count"]
    if "bufferView" in accessor:
        values = _read_view(asset, accessor["bufferView"], accessor.get("byteOffset", 0), count,
                            dtype, shape)
    else:
        values = np.zeros((count,) + shape, dtype=dtype)
    sparse = accessor.get("sparse")
    if sparse is not None:
        values = values.copy()
        n = sparse["count"]
        idx = sparse["indices"]
        indices = _read_view(asset, idx["bufferView"], idx.get("byteOffset", 0), n,
                             COMPONENT_DTYPES[idx["componentType"]], (1,)).reshape(n)
        val = sparse["values"]
        replaced = _read_view(asset, val["bufferView"], val.get("byteOffset", 0), n, dtype, shape)
        values[indices.astype(np.int64)] = replaced
    if not as_float:
        return values.astype(np.int64)
    if accessor.get("normalized", False):
        return _normalised(values, dtype)
    return values.astype(np.float64)


# --- transforms --------------------------------------------------------------

def quaternion_matrix(q):
    """3x3 rotation of the unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def trs_matrix(translation, rotation, scale):
    m = np.eye(4)
    m[:3, :3] = quaternion_matrix(rotation) * np.asarray(scale, dtype=np.float64)[None, :]
    m[:3, 3] = translation
    return m


def node_trs(node):
    return (np.array(node.get("translation", [0.0, 0.0, 0.0]), dtype=np.float64),
            np.array(node.get("rotation", [0.0, 0.0, 0.0, 1.0]), dtype=np.float64),
            np.array(node.get("scale", [1.0, 1.0, 1.0]), dtype=np.float64))


def local_matrices(asset, overrides=None):
    """Each node's local matrix: its matrix, or T * R * S from its TRS with any
    animated path replaced (overrides: {(node, path): value})."""
    overrides = overrides or {}
    out = []
    for i, node in enumerate(asset.gltf.get("nodes", [])):
        if "matrix" in node:
            if any((i, p) in overrides for p in ("translation", "rotation", "scale")):
                raise ValueError(f"node {i} has a matrix and is animated, which glTF forbids")
            out.append(np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T)
            continue
        t, r, s = node_trs(node)
        t = overrides.get((i, "translation"), t)
        r = overrides.get((i, "rotation"), r)
        s = overrides.get((i, "scale"), s)
        out.append(trs_matrix(t, r, s))
    return out


def world_matrices(asset, overrides=None):
    local = local_matrices(asset, overrides)
    world = [None] * len(local)

    def resolve(i):
        if world[i] is None:
            p = asset.parent[i]
            world[i] = local[i] if p is None else resolve(p) @ local[i]
        return world[i]

    for i in range(len(local)):
        resolve(i)
    return world


# --- animation sampling (Appendix C) ------------------------------------------

def _slerp(a, b, t):
    d = float(np.dot(a, b))
    if d < 0.0:
        b, d = -b, -d
    if d > 0.9999999:
        q = (1 - t) * a + t * b
        return q / np.linalg.norm(q)
    angle = np.arccos(min(d, 1.0))
    s = np.sin(angle)
    return (np.sin((1 - t) * angle) / s) * a + (np.sin(t * angle) / s) * b


def sample(asset, sampler, path, time):
    """The sampler's output at time (seconds), clamped to its keys' range."""
    times = asset.accessor(sampler["input"]).reshape(-1)
    output = asset.accessor(sampler["output"])
    interpolation = sampler.get("interpolation", "LINEAR")
    n = len(times)
    values = output.reshape(n * (3 if interpolation == "CUBICSPLINE" else 1), -1)
    if interpolation == "CUBICSPLINE":
        in_tangent, value, out_tangent = values[0::3], values[1::3], values[2::3]
    else:
        value = values
    if time <= times[0]:
        k, t = 0, 0.0
        result = value[0]
    elif time >= times[-1]:
        k, t = n - 1, 0.0
        result = value[-1]
    else:
        k = int(np.searchsorted(times, time, side="right")) - 1
        dt = times[k + 1] - times[k]
        t = (time - times[k]) / dt
        if interpolation == "STEP":
            result = value[k]
        elif interpolation == "LINEAR":
            if path == "rotation":
                result = _slerp(value[k], value[k + 1], t)
            else:
                result = (1 - t) * value[k] + t * value[k + 1]
        elif interpolation == "CUBICSPLINE":
            t2, t3 = t * t, t * t * t
            result = ((2 * t3 - 3 * t2 + 1) * value[k] + dt * (t3 - 2 * t2 + t) * out_tangent[k]
                      + (-2 * t3 + 3 * t2) * value[k + 1] + dt * (t3 - t2) * in_tangent[k + 1])
        else:
            raise ValueError(f"unknown interpolation {interpolation}")
    result = np.array(result, dtype=np.float64)
    if path == "rotation":
        result = result / np.linalg.norm(result)
    return result


def animation_names(asset):
    return [a.get("name", f"animation {i}") for i, a in enumerate(asset.gltf.get("animations", []))]


def animation_index(asset, animation):
    if isinstance(animation, int):
        return animation
    names = animation_names(asset)
    if animation not in names:
        raise KeyError(f"no animation named {animation!r} (the file has {names})")
    return names.index(animation)


def animation_range(asset, animation):
    a = asset.gltf["animations"][animation_index(asset, animation)]
    times = [asset.accessor(s["input"]).reshape(-1) for s in a["samplers"]]
    return min(float(t[0]) for t in times), max(float(t[-1]) for t in times)


def animated_values(asset, animation, time):
    """{(node, path): value} of an animation at time, clamped to its range."""
    if animation is None:
        return {}
    a = asset.gltf["animations"][animation_index(asset, animation)]
    start, end = animation_range(asset, animation)
    time = min(max(float(time), start), end)
    values = {}
    for channel in a["channels"]:
        target = channel["target"]
        if "node" not in target:
            continue
        path = target["path"]
        sampler = a["samplers"][channel["sampler"]]
        values[(target["node"], path)] = sample(asset, sampler, path, time)
    return values


# --- meshes, morph targets, skins ----------------------------------------------

def mesh_node(asset, mesh_or_node):
    """The index of the node that instances the mesh: mesh_or_node is a node
    (its index, or its name) with a mesh, or a mesh's name, which names the
    first node instancing that mesh."""
    nodes = asset.gltf.get("nodes", [])
    if isinstance(mesh_or_node, str):
        named = [i for i, node in enumerate(nodes)
                 if node.get("name") == mesh_or_node and "mesh" in node]
        if named:
            return named[0]
        meshes = [i for i, m in enumerate(asset.gltf.get("meshes", []))
                  if m.get("name") == mesh_or_node]
        instancing = [i for i, node in enumerate(nodes) if meshes and node.get("mesh") == meshes[0]]
        if not instancing:
            raise KeyError(f"no mesh node and no instanced mesh named {mesh_or_node!r}")
        return instancing[0]
    if "mesh" not in nodes[mesh_or_node]:
        raise KeyError(f"node {mesh_or_node} has no mesh")
    return mesh_or_node


def mesh_attribute(asset, mesh_index, name):
    """An attribute of every primitive of the mesh, concatenated, or None."""
    parts = []
    for prim in asset.gltf["meshes"][mesh_index]["primitives"]:
        if name not in prim["attributes"]:
            return None
        parts.append(asset.accessor(prim["attributes"][name]))
    return np.concatenate(parts)


def morph_weights_of(asset, node_index, animated):
    node = asset.gltf["nodes"][node_index]
    mesh = asset.gltf["meshes"][node["mesh"]]
    count = len(mesh["primitives"][0].get("targets", []))
    if (node_index, "weights") in animated:
        weights = animated[(node_index, "weights")].reshape(-1)
    elif "weights" in node:
        weights = node["weights"]
    elif "weights" in mesh:
        weights = mesh["weights"]
    else:
        weights = [0.0] * count
    weights = np.asarray(weights, dtype=np.float64).reshape(-1)
    if len(weights) != count:
        raise ValueError(f"node {node_index}: {len(weights)} morph weights for {count} targets")
    return weights


def morphed_positions(asset, mesh_index, weights):
    """POSITION plus the weighted POSITION deltas of every target, all
    primitives concatenated."""
    parts = []
    for prim in asset.gltf["meshes"][mesh_index]["primitives"]:
        p = asset.accessor(prim["attributes"]["POSITION"]).copy()
        for w, target in zip(weights, prim.get("targets", [])):
            if w != 0.0 and "POSITION" in target:
                p += w * asset.accessor(target["POSITION"])
        parts.append(p)
    return np.concatenate(parts)


def vertex_influences(asset, mesh_index):
    """(joints, weights): (N, 4k) arrays over every JOINTS_n / WEIGHTS_n set."""
    joints, weights = [], []
    n = 0
    while True:
        j = mesh_attribute_int(asset, mesh_index, f"JOINTS_{n}")
        w = mesh_attribute(asset, mesh_index, f"WEIGHTS_{n}")
        if j is None or w is None:
            break
        joints.append(j)
        weights.append(w)
        n += 1
    if not joints:
        return None, None
    return np.concatenate(joints, axis=1), np.concatenate(weights, axis=1)


def mesh_attribute_int(asset, mesh_index, name):
    parts = []
    for prim in asset.gltf["meshes"][mesh_index]["primitives"]:
        if name not in prim["attributes"]:
            return None
        parts.append(asset.integer_accessor(prim["attributes"][name]))
    return np.concatenate(parts)


def joint_matrices(asset, skin_index, world):
    """The specification's jointMatrix_j = globalTransform(joint_j) *
    inverseBindMatrix_j (identity where the skin gives none)."""
    skin = asset.gltf["skins"][skin_index]
    joints = skin["joints"]
    if "inverseBindMatrices" in skin:
        ibm = asset.accessor(skin["inverseBindMatrices"])
    else:
        ibm = np.broadcast_to(np.eye(4), (len(joints), 4, 4))
    return np.stack([world[j] @ ibm[k] for k, j in enumerate(joints)])


def vertex_matrices(asset, mesh_or_node, animation=None, time=0.0):
    """Each vertex's blended 4x4 transform from its (morphed) bind position to
    posed world space: sum_i w_i jointMatrix_i for a skinned node (whose own
    transform glTF ignores), the node's world matrix for an unskinned one."""
    node_index = mesh_node(asset, mesh_or_node)
    node = asset.gltf["nodes"][node_index]
    animated = animated_values(asset, animation, time)
    world = world_matrices(asset, animated)
    count = sum(asset.gltf["accessors"][p["attributes"]["POSITION"]]["count"]
                for p in asset.gltf["meshes"][node["mesh"]]["primitives"])
    if "skin" not in node:
        return np.broadcast_to(world[node_index], (count, 4, 4)).copy()
    joints, weights = vertex_influences(asset, node["mesh"])
    if joints is None:
        raise ValueError(f"node {node_index} has a skin but its mesh has no JOINTS_0/WEIGHTS_0")
    jm = joint_matrices(asset, node["skin"], world)
    if joints.max() >= len(jm):
        raise ValueError(f"joint index {joints.max()} beyond the skin's {len(jm)} joints")
    return np.einsum("vk,vkij->vij", weights, jm[joints])


def posed_positions(asset, mesh_or_node, animation=None, time=0.0, morph_weights=None,
                    extra_target=None):
    """The posed world position of every glTF vertex of the mesh (all its
    primitives, in file order): morph targets first (at morph_weights, else
    the animation's, the node's or the mesh's weights), plus extra_target at
    weight 1, then skinning (or the node's transform for a static mesh)."""
    node_index = mesh_node(asset, mesh_or_node)
    mesh_index = asset.gltf["nodes"][node_index]["mesh"]
    if morph_weights is None:
        morph_weights = morph_weights_of(asset, node_index, animated_values(asset, animation, time))
    p = morphed_positions(asset, mesh_index, np.asarray(morph_weights, dtype=np.float64))
    if extra_target is not None:
        extra_target = np.asarray(extra_target, dtype=np.float64)
        if extra_target.shape != p.shape:
            raise ValueError(f"extra_target has shape {extra_target.shape}, the mesh {p.shape}")
        p = p + extra_target
    m = vertex_matrices(asset, node_index, animation, time)
    return np.einsum("vij,vj->vi", m[:, :3, :3], p) + m[:, :3, 3]


def corrective(asset, mesh_or_node, animation, time, posed_displacement):
    """The bind-space morph delta d = L_v^-1 D' that moves each skinned vertex
    by posed_displacement (N, 3) at that pose; L_v is the 3x3 part of the
    vertex's blended matrix (skinning is affine in the bind position)."""
    m = vertex_matrices(asset, mesh_or_node, animation, time)
    displacement = np.asarray(posed_displacement, dtype=np.float64)
    return np.linalg.solve(m[:, :3, :3], displacement[..., None])[..., 0]
