# Imports a mesh file in headless Blender and writes what Blender sees as
# JSON, so tests can compare it with what Dualform wrote or computed.
#
# usage: blender -b --factory-startup --python blender_read.py -- [--axes gltf] FILE OUT_JSON...
#
# Each FILE (.gltf, .glb, .ply or .obj) is imported into an empty scene, so
# that one Blender start reads several. Its OUT_JSON:
#   {"file": FILE, "axes": "gltf" | "blender",
#    "objects": [{"name", "mesh", "vertex_count",
#                 "local": [x0, y0, z0, x1, ...],   mesh coordinates
#                 "world": [...],                   after the object's world matrix
#                 "shape_keys": [{"name", "positions": [...]}]}]}   local, "Basis" first
# sorted by object name. --axes gltf reports in glTF's +Y up axes, undoing
# the importer's (x, y, z) -> (x, -z, y); the default is Blender's own.
#
# Blender's glTF importer keeps each primitive's used vertices in the file's
# order and appends the primitives of a mesh one after another; it merges
# no vertices (its merge option is off by default), so a primitive whose
# every vertex is used comes back in the file's vertex order.
import json
import sys

import bpy


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    axes = "blender"
    if argv[:1] == ["--axes"] and len(argv) >= 2 and argv[1] in ("gltf", "blender"):
        axes = argv[1]
        argv = argv[2:]
    if not argv or len(argv) % 2:
        sys.exit("usage: blender -b --factory-startup --python blender_read.py -- "
                 "[--axes gltf] FILE OUT_JSON...")
    return list(zip(argv[0::2], argv[1::2])), axes


def import_file(path):
    lower = path.lower()
    if lower.endswith((".gltf", ".glb")):
        # Debian 12's numpy 1.24 dropped numpy.bool, which Blender 3.4's
        # glTF importer still uses: a packaging mismatch, patched here.
        import numpy
        numpy.bool = bool
        bpy.ops.import_scene.gltf(filepath=path)
    elif lower.endswith(".ply"):
        bpy.ops.import_mesh.ply(filepath=path)
    elif lower.endswith(".obj"):
        bpy.ops.wm.obj_import(filepath=path)
    else:
        sys.exit(f"blender_read: {path}: not a .gltf, .glb, .ply or .obj file")


def flat(points, axes):
    out = []
    for x, y, z in points:
        out += (x, z, -y) if axes == "gltf" else (x, y, z)
    return out


def describe(obj, axes):
    mesh = obj.data
    local = [v.co.copy() for v in mesh.vertices]
    world = [obj.matrix_world @ p for p in local]
    keys = []
    if mesh.shape_keys:
        for block in mesh.shape_keys.key_blocks:
            keys.append({"name": block.name, "positions": flat([p.co for p in block.data], axes)})
    return {"name": obj.name, "mesh": mesh.name, "vertex_count": len(mesh.vertices),
            "local": flat(local, axes), "world": flat(world, axes), "shape_keys": keys}


def read(path, out, axes):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    import_file(path)
    objects = sorted((o for o in bpy.context.scene.objects if o.type == "MESH"),
                     key=lambda o: o.name)
    with open(out, "w") as f:
        json.dump({"file": path, "axes": axes, "objects": [describe(o, axes) for o in objects]}, f)
    print(f"blender_read: {len(objects)} mesh objects of {path} into {out}")


def main():
    files, axes = args()
    for path, out in files:
        read(path, out, axes)


main()
