"""Just enough glTF writing for the reference's own tests: accessors over a
growing BIN buffer, written as .glb or as .gltf with the buffer in a data
URI."""

from __future__ import annotations

import base64
import json
import struct
from pathlib import Path

import numpy as np

import gltf_skinning as gs

COMPONENT_TYPES = {np.dtype(v): k for k, v in gs.COMPONENT_DTYPES.items()}
TYPES = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4", 16: "MAT4"}


class GltfWriter:
    def __init__(self, gltf: dict | None = None, blob: bytes = b""):
        self.gltf = json.loads(json.dumps(gltf)) if gltf else {"asset": {"version": "2.0"}}
        self.bin = bytearray(blob)
        self.gltf.setdefault("bufferViews", [])
        self.gltf.setdefault("accessors", [])

    def view(self, data: bytes, stride: int | None = None) -> int:
        self.bin += b"\0" * (-len(self.bin) % 4)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride is not None:
            view["byteStride"] = stride
        self.bin += data
        self.gltf["bufferViews"].append(view)
        return len(self.gltf["bufferViews"]) - 1

    def accessor(self, view: int | None, dtype, components: int, count: int, offset: int = 0,
                 normalized: bool = False, **extra) -> int:
        accessor = {"componentType": COMPONENT_TYPES[np.dtype(dtype)], "type": TYPES[components],
                    "count": count, **extra}
        if view is not None:
            accessor["bufferView"] = view
            if offset:
                accessor["byteOffset"] = offset
        if normalized:
            accessor["normalized"] = True
        self.gltf["accessors"].append(accessor)
        return len(self.gltf["accessors"]) - 1

    def array(self, values, dtype=np.float32, normalized: bool = False) -> int:
        """A tightly packed accessor of values (count, components)."""
        values = np.asarray(values, dtype=dtype)
        values = values.reshape(len(values), -1)
        extra = {}
        if values.dtype == np.float32 and values.shape[1] <= 4:
            extra = {"min": values.min(axis=0).tolist(), "max": values.max(axis=0).tolist()}
        return self.accessor(self.view(values.tobytes()), dtype, values.shape[1], len(values),
                             normalized=normalized, **extra)

    def matrices(self, values) -> int:
        """MAT4 accessor of (count, 4, 4) row-major matrices, stored column-major."""
        values = np.asarray(values, dtype=np.float32)
        view = self.view(values.transpose(0, 2, 1).tobytes())
        return self.accessor(view, np.float32, 16, len(values))

    def _finished(self) -> dict:
        self.bin += b"\0" * (-len(self.bin) % 4)
        gltf = json.loads(json.dumps(self.gltf))
        gltf["buffers"] = [{"byteLength": len(self.bin)}]
        return gltf

    def write_glb(self, path: Path) -> Path:
        gltf = self._finished()
        text = json.dumps(gltf).encode()
        text += b" " * (-len(text) % 4)
        body = (struct.pack("<II", len(text), 0x4E4F534A) + text
                + struct.pack("<II", len(self.bin), 0x004E4942) + bytes(self.bin))
        path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
        return path

    def write_gltf(self, path: Path) -> Path:
        gltf = self._finished()
        gltf["buffers"][0]["uri"] = ("data:application/octet-stream;base64,"
                                     + base64.b64encode(bytes(self.bin)).decode())
        path.write_text(json.dumps(gltf))
        return path

    def asset(self) -> gs.Asset:
        return gs.Asset(self._finished(), [bytes(self.bin)])
