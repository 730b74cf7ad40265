# Imports FBX files with Blender's own FBX importer and writes what it made
# as JSON, for the FBX tests: per file, each object (name, type), each mesh
# object's vertices in the file's control point order (its mesh data, before
# any modifier, in glTF axes: Blender's (x, y, z) as (x, z, -y), after the
# object's world matrix) and its shape keys' (name, value, positions the
# same way), each armature's bones, and the actions.
#
# usage: blender -b --factory-startup --python blender_fbx_read.py -- OUT.json FILE.fbx...
import json
import sys

import bpy


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) < 2:
        sys.exit("usage: blender -b --python blender_fbx_read.py -- OUT.json FILE.fbx...")
    return argv[0], argv[1:]


def world(obj, co):
    p = obj.matrix_world @ co
    return [p.x, p.z, -p.y]


def read(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.fbx(filepath=path)
    out = {"file": path, "objects": [], "actions": sorted(a.name for a in bpy.data.actions)}
    for obj in sorted(bpy.data.objects, key=lambda o: o.name):
        record = {"name": obj.name, "type": obj.type}
        if obj.type == "MESH":
            me = obj.data
            record["vertices"] = [c for v in me.vertices for c in world(obj, v.co)]
            record["shape_keys"] = []
            if me.shape_keys is not None:
                for kb in me.shape_keys.key_blocks:
                    record["shape_keys"].append({
                        "name": kb.name, "value": kb.value,
                        "positions": [c for p in kb.data for c in world(obj, p.co)]})
            record["armature"] = next((m.object.name for m in obj.modifiers
                                       if m.type == "ARMATURE" and m.object), "")
        elif obj.type == "ARMATURE":
            record["bones"] = sorted(b.name for b in obj.data.bones)
            ad = obj.animation_data
            record["action"] = ad.action.name if ad and ad.action else ""
        out["objects"].append(record)
    return out


def main():
    out_path, files = args()
    result = [read(f) for f in files]
    with open(out_path, "w") as f:
        json.dump(result, f)


main()
