# Imports FBX files with Blender's own FBX importer and writes what it made
# as JSON, for the FBX tests: per file, each object (name, type), each mesh
# object's vertices in the file's control point order (its mesh data, before
# any modifier, in glTF axes: Blender's (x, y, z) as (x, z, -y), after the
# object's world matrix) and its shape keys' (name, value, positions the
# same way), each armature's bones, and the actions. With --pose FRAME KEY,
# also each mesh object's evaluated mesh (shape keys, then the armature) at
# that frame of the imported action with the shape key KEY at value 1.
#
# usage: blender -b --factory-startup --python blender_fbx_read.py --
#            OUT.json [--pose FRAME KEY] FILE.fbx...
import json
import sys

import bpy


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    pose = None
    if len(argv) > 3 and argv[1] == "--pose":
        pose = (int(argv[2]), argv[3])
        argv = argv[:1] + argv[4:]
    if len(argv) < 2:
        sys.exit("usage: blender -b --python blender_fbx_read.py -- OUT.json "
                 "[--pose FRAME KEY] FILE.fbx...")
    return argv[0], pose, argv[1:]


def evaluated(obj, frame, key):
    if obj.data.shape_keys is not None and key in obj.data.shape_keys.key_blocks:
        obj.data.shape_keys.key_blocks[key].value = 1.0
    bpy.context.scene.frame_set(frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    try:
        return [c for v in mesh.vertices for c in world(ev, v.co)]
    finally:
        ev.to_mesh_clear()


def world(obj, co):
    p = obj.matrix_world @ co
    return [p.x, p.z, -p.y]


def read(path, pose):
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
            if pose is not None:
                record["posed"] = evaluated(obj, *pose)
        elif obj.type == "ARMATURE":
            record["bones"] = sorted(b.name for b in obj.data.bones)
            ad = obj.animation_data
            record["action"] = ad.action.name if ad and ad.action else ""
        out["objects"].append(record)
    return out


def main():
    out_path, pose, files = args()
    result = [read(f, pose) for f in files]
    with open(out_path, "w") as f:
        json.dump(result, f)


main()
