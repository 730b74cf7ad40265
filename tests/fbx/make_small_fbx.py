# Writes the small FBX files in tests/data/fbx/ with Blender's own exporter
# (the unit tests' inputs and the FBX fuzz target's seeds): what an artist's
# tool writes, small enough to fuzz.
#   cube.fbx   a cube subdivided once (26 control points), its own UVs, the
#              shape key "Dent" at value 0.5
#   strip.fbx  a strip of 2 x 6 quads bound to a 2-bone armature with an
#              action "Bend" of 3 keys
# Then tests/fbx/fbx_convert.py makes strip-ascii.fbx and strip-7500.fbx.
#
# usage: blender -b -t 1 --factory-startup --python make_small_fbx.py -- OUT_DIR
#        (with PYTHONHASHSEED=0, as tests/skin/make-rigged-assets runs Blender,
#        for the same bytes on every run)
import datetime
import math
import sys

import bpy
import mathutils


def export(path):
    from io_scene_fbx import export_fbx_bin
    header = export_fbx_bin.fbx_header_elements

    def pinned(root, scene_data, time=None):
        header(root, scene_data, datetime.datetime(2020, 1, 1))

    export_fbx_bin.fbx_header_elements = pinned
    try:
        bpy.ops.export_scene.fbx(filepath=path)
    finally:
        export_fbx_bin.fbx_header_elements = header


def cube(out):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    obj = bpy.context.active_object
    obj.name = obj.data.name = "Cube"
    sub = obj.modifiers.new("subdivision", "SUBSURF")
    sub.levels = 1
    sub.subdivision_type = "SIMPLE"
    bpy.ops.object.modifier_apply(modifier=sub.name)
    obj.shape_key_add(name="Basis", from_mix=False)
    dent = obj.shape_key_add(name="Dent", from_mix=False)
    for point in dent.data:
        if point.co.z > 0.4:
            point.co.z -= 0.2 * (1.0 - max(abs(point.co.x), abs(point.co.y)))
    dent.value = 0.5
    export(f"{out}/cube.fbx")


def strip(out):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = 24
    verts = [(0.2 * i, 0.1 * j, 0.0) for i in range(7) for j in range(3)]
    faces = [(3 * i + j, 3 * (i + 1) + j, 3 * (i + 1) + j + 1, 3 * i + j + 1)
             for i in range(6) for j in range(2)]
    mesh = bpy.data.meshes.new("Strip")
    mesh.from_pydata(verts, [], faces)
    obj = bpy.data.objects.new("Strip", mesh)
    scene.collection.objects.link(obj)
    arm = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", arm)
    scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    root = arm.edit_bones.new("Root")
    root.head, root.tail = (0.0, 0.1, 0.0), (0.6, 0.1, 0.0)
    tip = arm.edit_bones.new("Tip")
    tip.head, tip.tail = (0.6, 0.1, 0.0), (1.2, 0.1, 0.0)
    tip.parent = root
    tip.use_connect = True
    bpy.ops.object.mode_set(mode="OBJECT")
    for name in ("Root", "Tip"):
        group = obj.vertex_groups.new(name=name)
        for v in mesh.vertices:
            t = min(max((v.co.x - 0.4) / 0.4, 0.0), 1.0)
            group.add([v.index], (1.0 - t) if name == "Root" else t, "REPLACE")
    obj.parent = rig
    obj.modifiers.new("armature", "ARMATURE").object = rig
    rig.animation_data_create()
    action = bpy.data.actions.new("Bend")
    rig.animation_data.action = action
    bone = rig.pose.bones["Tip"]
    bone.rotation_mode = "QUATERNION"
    for frame, degrees in ((1, 0.0), (7, 45.0), (13, 0.0)):
        bone.rotation_quaternion = mathutils.Quaternion((0.0, 0.0, 1.0), math.radians(degrees))
        bone.keyframe_insert("rotation_quaternion", frame=frame)
    scene.frame_start, scene.frame_end = 1, 13
    scene.frame_set(1)
    export(f"{out}/strip.fbx")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        sys.exit("usage: blender -b --python make_small_fbx.py -- OUT_DIR")
    cube(argv[0])
    strip(argv[0])


main()
