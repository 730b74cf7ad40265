# Imports a glTF in headless Blender and writes what an animator would see
# of it as JSON: the objects and their types, the armatures, the actions,
# each mesh's shape keys, and the skinned mesh as Blender evaluates it at a
# frame with one shape key at 1 (Blender applies shape keys before the
# Armature modifier).
#
# usage: blender -b --factory-startup --python blender_pose_check.py -- GLB ACTION FRAME KEY OUT_JSON
#
# ACTION is played on every armature (the importer names an action after the
# glTF animation, with the armature's name after it where it makes several).
# OUT_JSON: {"objects": [{"name", "type"}], "actions": [names],
#            "shape_keys": {mesh object: [names]},
#            "evaluated": [x0, y0, z0, ...],   the key at 1
#            "unkeyed": [...]}                 the key at 0
# world space, glTF axes (x, z, -y): the evaluated vertices of the object
# that has the key, in Blender's order (the importer keeps a primitive's
# vertices in the file's order).
import json
import sys

import bpy


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    if len(argv) != 5:
        sys.exit("usage: blender -b --factory-startup --python blender_pose_check.py -- "
                 "GLB ACTION FRAME KEY OUT_JSON")
    path, action, frame, key, out = argv[0], argv[1], int(argv[2]), argv[3], argv[4]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Debian 12's numpy 1.24 dropped numpy.bool, which Blender 3.4's glTF
    # importer still uses: a packaging mismatch, patched here.
    import numpy
    numpy.bool = bool
    bpy.ops.import_scene.gltf(filepath=path)
    scene = bpy.context.scene
    report = {"objects": [], "actions": sorted(a.name for a in bpy.data.actions),
              "shape_keys": {}, "evaluated": []}
    keyed = None
    for obj in sorted(scene.objects, key=lambda o: o.name):
        report["objects"].append({"name": obj.name, "type": obj.type})
        if obj.type != "MESH" or obj.data.shape_keys is None:
            continue
        names = [b.name for b in obj.data.shape_keys.key_blocks]
        report["shape_keys"][obj.name] = names
        if key in names:
            keyed = obj
    played = [a for a in bpy.data.actions if a.name == action or a.name.startswith(action + "_")]
    for obj in scene.objects:
        if obj.type == "ARMATURE" and played:
            obj.animation_data_create().action = played[0]
    if keyed is not None:
        scene.frame_set(frame)
        block = keyed.data.shape_keys.key_blocks[key]
        for value, field in ((0.0, "unkeyed"), (1.0, "evaluated")):
            block.value = value
            depsgraph = bpy.context.evaluated_depsgraph_get()
            evaluated = keyed.evaluated_get(depsgraph)
            mesh = evaluated.to_mesh()
            world = evaluated.matrix_world
            report[field] = []
            for v in mesh.vertices:
                x, y, z = world @ v.co
                report[field] += [x, z, -y]
            evaluated.to_mesh_clear()
    with open(out, "w") as f:
        json.dump(report, f)


main()
