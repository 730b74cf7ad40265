# Writes real game-style glTF assets with Blender's own exporter, for the
# glTF tests: what an artist's tool writes, seams and all.
#
# usage: blender -b --factory-startup --python make_assets.py -- OUT_DIR COW_OFF
#
# OUT_DIR receives:
#   suzanne.glb           Suzanne, subdivision surface level 2 applied (7,958
#                         vertices), triangulated, smooth shaded, her own UVs
#                         (the seams split vertices), tangents
#   suzanne.off           the same surface welded, in glTF axes, exact float32
#   cow.glb               the cow from COW_OFF, flat shaded, smart UV project
#   cow.gltf + cow.bin    the same, JSON with a separate buffer
#   cow-embedded.gltf     the same, buffer embedded as a data URI
#   cow.off               the cow's surface in glTF axes, exact float32
#   scene.glb             two meshes under transformed nodes: "Cow" (smooth,
#                         UVs, a material, the shape key "Squash") and "Ball"
#                         (a material, an animation, node extras)
#
# The .off files are the welded surfaces the glTF files split, written from
# the very float32 values Blender exports, so an edit of the glTF and of the
# OFF can agree to rounding. glTF is +Y up, Blender +Z up: the exporter
# writes (x, z, -y), and so do the .off files.
import sys

import bmesh
import bpy


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 2:
        sys.exit("usage: blender -b --factory-startup --python make_assets.py -- OUT_DIR COW_OFF")
    return argv


def read_off(path):
    words = []
    with open(path) as f:
        for line in f:
            words += line.split("#", 1)[0].split()
    if not words or words[0] != "OFF":
        sys.exit(f"{path}: not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    at = 4
    verts = []
    for _ in range(nv):
        verts.append(tuple(float(w) for w in words[at:at + 3]))
        at += 3
    faces = []
    for _ in range(nf):
        n = int(words[at])
        faces.append(tuple(int(w) for w in words[at + 1:at + 1 + n]))
        at += 1 + n
    return verts, faces


def clear_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def to_blender_axes(p):
    # The inverse of the exporter's (x, y, z) -> (x, z, -y).
    x, y, z = p
    return (x, -z, y)


def write_off(obj, path):
    # Vertices as the exporter writes them: float32 in glTF axes. repr of the
    # float32 value widened to double is exact.
    mesh = obj.data
    with open(path, "w") as f:
        f.write(f"OFF\n{len(mesh.vertices)} {len(mesh.polygons)} 0\n")
        for v in mesh.vertices:
            x, y, z = v.co
            f.write(f"{x!r} {z!r} {-y!r}\n")
        for p in mesh.polygons:
            f.write(f"{len(p.vertices)} " + " ".join(str(i) for i in p.vertices) + "\n")


def new_object(name, verts, faces):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.validate()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def set_smooth(obj, smooth):
    for p in obj.data.polygons:
        p.use_smooth = smooth


def smart_uv_project(obj):
    bpy.context.view_layer.objects.active = obj
    for o in bpy.context.view_layer.objects:
        o.select_set(o is obj)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(angle_limit=1.15, island_margin=0.01)
    bpy.ops.object.mode_set(mode="OBJECT")


def material(name, rgba):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    m.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = rgba
    return m


def export(path, fmt, **options):
    bpy.ops.export_scene.gltf(filepath=path, export_format=fmt, export_apply=False,
                              export_yup=True, **options)


def suzanne(out):
    clear_scene()
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    obj.name = obj.data.name = "Suzanne"
    sub = obj.modifiers.new("subdivision", "SUBSURF")
    sub.levels = sub.render_levels = 2
    bpy.ops.object.modifier_apply(modifier=sub.name)
    if len(obj.data.vertices) != 7958:
        sys.exit(f"Suzanne at subdivision level 2 has {len(obj.data.vertices)} vertices, not 7958")
    # Triangulated before export, so the glTF's triangles are the OFF's.
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    bm.to_mesh(obj.data)
    bm.free()
    set_smooth(obj, True)
    write_off(obj, f"{out}/suzanne.off")
    export(f"{out}/suzanne.glb", "GLB", export_tangents=True)


def cow_object(cow_off, name):
    verts, faces = read_off(cow_off)
    return new_object(name, [to_blender_axes(v) for v in verts], faces)


def cow(out, cow_off):
    clear_scene()
    obj = cow_object(cow_off, "Cow")
    set_smooth(obj, False)
    smart_uv_project(obj)
    write_off(obj, f"{out}/cow.off")
    export(f"{out}/cow.glb", "GLB")
    export(f"{out}/cow.gltf", "GLTF_SEPARATE")
    export(f"{out}/cow-embedded.gltf", "GLTF_EMBEDDED")


def scene(out, cow_off):
    clear_scene()
    rig = bpy.data.objects.new("Rig", None)
    bpy.context.scene.collection.objects.link(rig)
    rig.location = (0.5, -0.25, 0.125)
    rig.rotation_euler = (0.0, 0.0, 0.5)
    rig.scale = (2.0, 2.0, 2.0)

    cow_obj = cow_object(cow_off, "Cow")
    cow_obj.parent = rig
    cow_obj.location = (0.0, 1.0, 0.25)
    cow_obj.rotation_euler = (0.25, 0.0, 0.0)
    set_smooth(cow_obj, True)
    smart_uv_project(cow_obj)
    cow_obj.data.materials.append(material("Hide", (0.8, 0.6, 0.4, 1.0)))
    cow_obj.shape_key_add(name="Basis")
    squash = cow_obj.shape_key_add(name="Squash")
    for point in squash.data:
        point.co.z *= 0.75

    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=0.25)
    ball = bpy.context.active_object
    ball.name = ball.data.name = "Ball"
    ball.parent = rig
    ball.location = (1.0, 0.0, 0.5)
    ball.data.materials.append(material("Rubber", (0.2, 0.3, 0.9, 1.0)))
    ball["bounce"] = 0.75
    ball.keyframe_insert("location", frame=1)
    ball.location.z = 1.0
    ball.keyframe_insert("location", frame=12)

    export(f"{out}/scene.glb", "GLB", export_extras=True, export_animations=True,
           export_morph=True, export_morph_normal=True)


def main():
    out, cow_off = args()
    suzanne(out)
    cow(out, cow_off)
    scene(out, cow_off)
    print("make_assets: wrote the assets into", out)


main()
