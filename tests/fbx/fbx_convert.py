"""Rewrites a binary FBX file for the FBX tests, independently of the
engine's reader and writer: as ASCII FBX 7.x text (--ascii), or as binary
FBX 7.5 with 64-bit node headers (--7500). Every node and value is kept.

usage: python3 fbx_convert.py --ascii|--7500 IN.fbx OUT.fbx
"""

from __future__ import annotations

import struct
import sys
import zlib

MAGIC = b"Kaydara FBX Binary  \x00\x1a\x00"
ARRAY = {"f": ("<f", 4), "d": ("<d", 8), "l": ("<q", 8), "i": ("<i", 4), "b": ("<B", 1),
         "c": ("<B", 1)}
SCALAR = {"Y": "<h", "C": "<?", "I": "<i", "F": "<f", "D": "<d", "L": "<q"}


class Node:
    def __init__(self, name, props, children, null_record):
        self.name, self.props, self.children, self.null_record = name, props, children, null_record


def read_props(data, at, count):
    props = []
    for _ in range(count):
        code = chr(data[at])
        at += 1
        if code in SCALAR:
            fmt = SCALAR[code]
            props.append((code, struct.unpack_from(fmt, data, at)[0], data[at - 1:at + struct.calcsize(fmt)]))
            at += struct.calcsize(fmt)
        elif code in "SR":
            (n,) = struct.unpack_from("<I", data, at)
            props.append((code, data[at + 4:at + 4 + n], data[at - 1:at + 4 + n]))
            at += 4 + n
        elif code in ARRAY:
            n, encoding, stored = struct.unpack_from("<III", data, at)
            raw = data[at + 12:at + 12 + stored]
            values = zlib.decompress(raw) if encoding == 1 else raw
            fmt, width = ARRAY[code]
            items = [struct.unpack_from(fmt, values, k * width)[0] for k in range(n)]
            props.append((code, items, data[at - 1:at + 12 + stored]))
            at += 12 + stored
        else:
            raise ValueError(f"unknown property type {code!r} at byte {at - 1}")
    return props


def read_nodes(data, at, end, wide):
    head = "<QQQB" if wide else "<IIIB"
    size = struct.calcsize(head)
    nodes = []
    while at < end:
        node_end, count, length, name_length = struct.unpack_from(head, data, at)
        if node_end == 0:
            return nodes, at + size
        name = data[at + size:at + size + name_length].decode("ascii")
        props_at = at + size + name_length
        props = read_props(data, props_at, count)
        children_at = props_at + length
        children = []
        if children_at < node_end:
            children, _ = read_nodes(data, children_at, node_end - size, wide)
        nodes.append(Node(name, props, children, children_at < node_end))
        at = node_end
    return nodes, at


def load(path):
    data = open(path, "rb").read()
    assert data.startswith(MAGIC), f"{path} is not binary FBX"
    (version,) = struct.unpack_from("<I", data, len(MAGIC))
    nodes, footer = read_nodes(data, len(MAGIC) + 4, len(data), version >= 7500)
    return version, nodes, data[footer:]


def ascii_value(code, value):
    if code == "S":
        # ASCII FBX writes "Name\0\1Class" as "Class::Name".
        text = value.decode("utf-8", "replace")
        if "\x00\x01" in text:
            name, cls = text.split("\x00\x01", 1)
            text = f"{cls}::{name}"
        return '"' + text.replace('"', "&quot;") + '"'
    if code == "R":
        return '"' + value.hex() + '"'
    if code == "C":
        return "T" if value else "F"
    if code in "FD":
        return repr(float(value))
    return str(int(value))


def write_ascii(nodes, version, out, depth=0):
    pad = "\t" * depth
    for n in nodes:
        values = []
        array = None
        for code, value, _ in n.props:
            if code in ARRAY:
                array = (code, value)
            else:
                values.append(ascii_value(code, value))
        line = f"{pad}{n.name}: " + ", ".join(values)
        if array is not None:
            code, items = array
            text = ",".join(repr(float(v)) if code in "fd" else str(int(v)) for v in items)
            line += f"*{len(items)} {{\n{pad}\ta: {text}\n{pad}}}"
            out.write(line + "\n")
            continue
        if n.children or n.null_record:
            out.write(line + " {\n")
            write_ascii(n.children, version, out, depth + 1)
            out.write(pad + "}\n")
        else:
            out.write(line + "\n")


def to_ascii(src, dst):
    version, nodes, _ = load(src)
    with open(dst, "w", encoding="utf-8") as out:
        major, minor = divmod(version, 1000)
        out.write(f"; FBX {major}.{minor // 100}.{minor % 100} project file\n")
        out.write("; written by tests/fbx/fbx_convert.py from a binary file\n\n")
        write_ascii(nodes, version, out)


def encode(nodes, wide, out):
    head = "<QQQB" if wide else "<IIIB"
    size = struct.calcsize(head)
    for n in nodes:
        at = len(out)
        out += b"\0" * size
        out += n.name.encode("ascii")
        props = b"".join(raw for _, _, raw in n.props)
        out += props
        if n.children or n.null_record:
            encode(n.children, wide, out)
            out += b"\0" * size
        struct.pack_into(head, out, at, len(out), len(n.props), len(props), len(n.name))


def to_7500(src, dst):
    _, nodes, footer = load(src)
    for n in nodes:
        if n.name == "FBXHeaderExtension":
            for c in n.children:
                if c.name == "FBXVersion":
                    c.props = [("I", 7500, b"I" + struct.pack("<i", 7500))]
    out = bytearray(MAGIC + struct.pack("<I", 7500))
    encode(nodes, True, out)
    out += b"\0" * 25
    # The footer: its id, 4 zeros, padding to 16 bytes, the version, 120
    # zeros and the magic.
    out += footer[:16] + b"\0" * 4
    pad = ((len(out) + 15) & ~15) - len(out)
    out += b"\0" * (pad or 16)
    out += struct.pack("<I", 7500) + b"\0" * 120 + footer[-16:]
    open(dst, "wb").write(out)


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("--ascii", "--7500"):
        sys.exit(__doc__)
    (to_ascii if sys.argv[1] == "--ascii" else to_7500)(sys.argv[2], sys.argv[3])


if __name__ == "__main__":
    main()
