# Writes rigged (skinned, animated) test assets with Blender's own glTF and
# FBX exporters, and Blender's own evaluated (posed) meshes beside them, for
# the skinned-character tests: what an artist's tool writes, seams and all.
#
# usage: blender -b -t 1 --factory-startup --python make_rigged_assets.py -- OUT_DIR
#        (make-rigged-assets runs it so, with PYTHONHASHSEED=0)
#
# OUT_DIR receives each asset as NAME.glb (glTF, +Y up) and NAME.fbx
# (Blender's FBX exporter with its defaults: binary FBX 7.4, armature, every
# action baked, shape keys as blend shapes):
#   arm        a 2 m tube bent 25 degrees at the elbow, 64 rings of 48
#              vertices and a fan at each end (3,074 vertices), smooth, UV
#              seams along its length and around the caps; an armature of 2
#              bones (UpperArm, Forearm), automatic weights; the action "Wave"
#              (frames 1-37) keys the shoulder's rotation and location, the
#              elbow's rotation and the forearm's scale (Bezier keys, which
#              the glTF exporter samples per frame as LINEAR)
#   arm-morph  the same arm with the shape key "Flex" (a bulge of the upper
#              arm) at value 0.25, under the armature
#   humanoid   a figure made by the Skin modifier from a stick skeleton,
#              subdivided three times (13,922 vertices), smart-UV-projected,
#              with a 19-bone armature (Hips, Spine, Chest, Neck, Head, and per
#              side Shoulder, UpperArm, Forearm, Hand, Thigh, Shin, Foot) whose
#              object is moved and turned; automatic weights limited to 4 per
#              vertex and normalised. Three actions, exported unsampled so
#              their keys' interpolation reaches the file: "Walk" (linear
#              keys: glTF LINEAR; translation, rotation and scale), "Hold"
#              (constant keys: STEP) and "Sway" (Bezier keys whose handles lie
#              at a third of each interval: CUBICSPLINE)
#   humanoid-20k  the same figure and rig from a stick skeleton whose bones are
#              cut in three before the Skin modifier (20,066 vertices): the
#              size the pose and bake figures of docs/benchmarks.md are taken at
#   prop       Suzanne subdivided once (2,012 vertices), her own UVs, no armature
#   shapekey   a cube subdivided three times (386 vertices), its own UVs, the
#              shape keys "Bulge" (value 0.0) and "Pinch" (value 0.3)
#
# and for each skinned asset NAME.frames.json, Blender's evaluated mesh:
#   mesh, armature, fps, bones (names), vertex_count
#   rest_positions   the mesh's own vertices (no shape key, no armature) in
#                    world space, Blender's vertex order: where a skinned glb
#                    from Blender holds its POSITION
#   frames           [{animation, frame, time_seconds, positions}]: the
#                    evaluated mesh (shape keys, then the Armature modifier)
#                    in world space at that frame of that action; time_seconds
#                    is frame / fps rounded to float32, as the glTF exporter
#                    writes key times, so a key's frame falls on its key
# All positions in glTF axes: Blender's (x, y, z) is written (x, z, -y).
#
# Deterministic: no randomness, and the FBX header's creation time is pinned.
import datetime
import json
import math
import sys

import bmesh
import bpy
import mathutils
import numpy as np

FPS = 24


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        sys.exit("usage: blender -b -t 1 --factory-startup --python make_rigged_assets.py "
                 "-- OUT_DIR")
    return argv[0]


def clear_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.render.fps_base = 1.0


def link(obj):
    bpy.context.scene.collection.objects.link(obj)
    return obj


def select_only(obj):
    for o in bpy.context.view_layer.objects:
        o.select_set(o is obj)
    bpy.context.view_layer.objects.active = obj


def smoothstep(x):
    x = min(max(x, 0.0), 1.0)
    return x * x * (3.0 - 2.0 * x)


# --- the arm -----------------------------------------------------------------

ARM_LENGTH = 2.0
ARM_ELBOW = 1.0
ARM_BEND = math.radians(25.0)
ARM_RINGS = 64
ARM_SEGMENTS = 48


def arm_frame(s):
    """Centre and normal of the arm's centreline at arc length s: straight
    along +X, turning up (+Z) by ARM_BEND across the elbow."""
    steps = 400
    x = z = 0.0
    h = s / steps
    for k in range(steps):
        phi = ARM_BEND * smoothstep(((k + 0.5) * h - (ARM_ELBOW - 0.15)) / 0.3)
        x += h * math.cos(phi)
        z += h * math.sin(phi)
    phi = ARM_BEND * smoothstep((s - (ARM_ELBOW - 0.15)) / 0.3)
    return mathutils.Vector((x, 0.0, z)), mathutils.Vector((-math.sin(phi), 0.0, math.cos(phi)))


def arm_radius(s):
    t = s / ARM_LENGTH
    return 0.12 - 0.035 * t + 0.015 * math.sin(math.pi * t * 2.0) ** 2


def arm_mesh(name):
    """A tube of ARM_RINGS rings of ARM_SEGMENTS vertices along the bent
    centreline, closed by a fan at each end; UVs: the tube unrolled (seam along
    its length) and each cap its own disc."""
    verts, faces, uvs = [], [], []
    side = mathutils.Vector((0.0, 1.0, 0.0))
    for i in range(ARM_RINGS):
        s = ARM_LENGTH * i / (ARM_RINGS - 1)
        centre, normal = arm_frame(s)
        r = arm_radius(s)
        for j in range(ARM_SEGMENTS):
            a = 2.0 * math.pi * j / ARM_SEGMENTS
            verts.append(centre + r * (math.cos(a) * normal + math.sin(a) * side))
    start = len(verts)
    verts.append(arm_frame(0.0)[0])
    verts.append(arm_frame(ARM_LENGTH)[0])

    def ring(i, j):
        return i * ARM_SEGMENTS + j % ARM_SEGMENTS

    for i in range(ARM_RINGS - 1):
        for j in range(ARM_SEGMENTS):
            faces.append((ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)))
            v0, v1 = 0.05 + 0.6 * i / (ARM_RINGS - 1), 0.05 + 0.6 * (i + 1) / (ARM_RINGS - 1)
            u0, u1 = 0.05 + 0.9 * j / ARM_SEGMENTS, 0.05 + 0.9 * (j + 1) / ARM_SEGMENTS
            uvs.append(((u0, v0), (u0, v1), (u1, v1), (u1, v0)))
    for end, i, centre_uv in ((start, 0, (0.2, 0.82)), (start + 1, ARM_RINGS - 1, (0.6, 0.82))):
        for j in range(ARM_SEGMENTS):
            tri = (end, ring(i, j + 1), ring(i, j)) if i == 0 else (end, ring(i, j), ring(i, j + 1))
            faces.append(tri)
            corner = []
            for v in tri:
                if v == end:
                    corner.append(centre_uv)
                else:
                    a = 2.0 * math.pi * (v % ARM_SEGMENTS) / ARM_SEGMENTS
                    corner.append((centre_uv[0] + 0.15 * math.cos(a),
                                   centre_uv[1] + 0.15 * math.sin(a)))
            uvs.append(tuple(corner))

    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(v) for v in verts], [], faces)
    layer = mesh.uv_layers.new(name="UVMap")
    for poly, corners in zip(mesh.polygons, uvs):
        for loop, uv in zip(poly.loop_indices, corners):
            layer.data[loop].uv = uv
    mesh.validate()
    for p in mesh.polygons:
        p.use_smooth = True
    mark_uv_seams(mesh)
    return mesh


def mark_uv_seams(mesh):
    """Marks as seams the edges whose two faces disagree on UVs, as an artist's
    unwrap would have them."""
    bm = bmesh.new()
    bm.from_mesh(mesh)
    uv = bm.loops.layers.uv.active
    for edge in bm.edges:
        loops = []
        for face_loop in edge.link_loops:
            a, b = face_loop, face_loop.link_loop_next
            by_vert = {a.vert.index: tuple(a[uv].uv), b.vert.index: tuple(b[uv].uv)}
            loops.append(by_vert)
        edge.seam = len(loops) == 2 and loops[0] != loops[1]
    bm.to_mesh(mesh)
    bm.free()


def armature_object(name, bones):
    """bones: (name, head, tail, parent or None, connected), in Blender axes."""
    data = bpy.data.armatures.new(name)
    obj = link(bpy.data.objects.new(name, data))
    select_only(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    made = {}
    for bone_name, head, tail, parent, connected in bones:
        bone = data.edit_bones.new(bone_name)
        bone.head, bone.tail = head, tail
        bone.roll = 0.0
        if parent is not None:
            bone.parent = made[parent]
            bone.use_connect = connected
        made[bone_name] = bone
    bpy.ops.object.mode_set(mode="OBJECT")
    return obj


def skin_to(mesh_obj, rig, max_influences):
    """Automatic (bone heat) weights, then at most max_influences per vertex,
    normalised, as game exports have them."""
    mesh_obj.select_set(True)
    rig.select_set(True)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    select_only(mesh_obj)
    bpy.ops.object.vertex_group_limit_total(group_select_mode="ALL", limit=max_influences)
    bpy.ops.object.vertex_group_normalize_all(group_select_mode="ALL", lock_active=False)
    unweighted = [v.index for v in mesh_obj.data.vertices
                  if sum(g.weight for g in v.groups) < 0.999]
    if unweighted:
        sys.exit(f"{mesh_obj.name}: {len(unweighted)} vertices without full weight "
                 f"after automatic weights (first {unweighted[:5]})")


def quat(axis, degrees):
    return mathutils.Quaternion(axis, math.radians(degrees))


def key_pose(rig, frame, pose):
    """pose: {bone: {"rotation_quaternion"|"location"|"scale": value}}"""
    for bone_name, channels in pose.items():
        pb = rig.pose.bones[bone_name]
        for path, value in channels.items():
            setattr(pb, path, value)
            pb.keyframe_insert(path, frame=frame, group=bone_name)


def new_action(rig, name):
    reset_pose(rig)
    if rig.animation_data is None:
        rig.animation_data_create()
    action = bpy.data.actions.new(name)
    rig.animation_data.action = action
    return action


def reset_pose(rig):
    for pb in rig.pose.bones:
        pb.rotation_mode = "QUATERNION"
        pb.location = (0.0, 0.0, 0.0)
        pb.rotation_quaternion = (1.0, 0.0, 0.0, 0.0)
        pb.scale = (1.0, 1.0, 1.0)


def set_interpolation(action, interpolation):
    for fc in action.fcurves:
        for kp in fc.keyframe_points:
            kp.interpolation = interpolation
        fc.update()


def third_handles(action):
    """Bezier handles a third of the way to each neighbouring key: the curve
    between two keys is then the cubic Hermite spline of glTF's CUBICSPLINE in
    time, with the handles' slopes as its tangents, so the file describes
    exactly what Blender evaluates. Slopes are Catmull-Rom's, except that a
    rotation's is bent to end on the unit sphere (q + slope a unit
    quaternion): Blender 3.4's exporter normalises q + slope before taking the
    tangent, which changes any other slope."""
    groups = {}
    for fc in action.fcurves:
        groups.setdefault(fc.data_path, []).append(fc)
    for path, curves in groups.items():
        curves.sort(key=lambda fc: fc.array_index)
        times = [kp.co[0] for kp in curves[0].keyframe_points]
        values = np.array([[kp.co[1] for kp in fc.keyframe_points] for fc in curves]).T
        slopes = np.empty_like(values)
        for k in range(len(times)):
            a, b = max(k - 1, 0), min(k + 1, len(times) - 1)
            slopes[k] = (values[b] - values[a]) / (times[b] - times[a])
            if path.endswith("rotation_quaternion"):
                unit = values[k] + slopes[k]
                slopes[k] = unit / np.linalg.norm(unit) - values[k]
        for c, fc in enumerate(curves):
            for k, kp in enumerate(fc.keyframe_points):
                kp.interpolation = "BEZIER"
                kp.handle_left_type = kp.handle_right_type = "FREE"
                t, v, slope = times[k], values[k, c], slopes[k, c]
                dl = (t - times[k - 1]) / 3.0 if k > 0 else (times[1] - t) / 3.0
                dr = (times[k + 1] - t) / 3.0 if k + 1 < len(times) else dl
                kp.handle_left = (t - dl, v - slope * dl)
                kp.handle_right = (t + dr, v + slope * dr)
            fc.update()


def arm_rig():
    elbow = arm_frame(ARM_ELBOW)[0]
    tip = arm_frame(ARM_LENGTH)[0]
    return armature_object("ArmRig", [
        ("UpperArm", (0.0, 0.0, 0.0), tuple(elbow), None, False),
        ("Forearm", tuple(elbow), tuple(tip), "UpperArm", True),
    ])


def wave(rig):
    action = new_action(rig, "Wave")
    # Bone axes: Y along the bone; the elbow bends about the forearm's X.
    key_pose(rig, 1, {"UpperArm": {"rotation_quaternion": quat((0, 0, 1), 0.0),
                                   "location": (0.0, 0.0, 0.0)},
                      "Forearm": {"rotation_quaternion": quat((1, 0, 0), 0.0),
                                  "scale": (1.0, 1.0, 1.0)}})
    key_pose(rig, 13, {"UpperArm": {"rotation_quaternion": quat((0.3, 0.2, 1), 40.0),
                                    "location": (0.0, 0.04, 0.02)},
                       "Forearm": {"rotation_quaternion": quat((1, 0, 0.2), 85.0),
                                   "scale": (1.0, 1.12, 1.0)}})
    key_pose(rig, 25, {"UpperArm": {"rotation_quaternion": quat((-0.2, 0.5, 1), 25.0),
                                    "location": (0.0, 0.0, 0.03)},
                       "Forearm": {"rotation_quaternion": quat((1, 0, -0.1), 110.0),
                                   "scale": (1.0, 0.95, 1.0)}})
    key_pose(rig, 37, {"UpperArm": {"rotation_quaternion": quat((0, 0, 1), 0.0),
                                    "location": (0.0, 0.0, 0.0)},
                       "Forearm": {"rotation_quaternion": quat((1, 0, 0), 0.0),
                                   "scale": (1.0, 1.0, 1.0)}})
    return action


def flex_key(obj):
    """A bulge of the upper arm's top, outward along the tube's normal."""
    obj.shape_key_add(name="Basis", from_mix=False)
    flex = obj.shape_key_add(name="Flex", from_mix=False)
    for i in range(ARM_RINGS):
        s = ARM_LENGTH * i / (ARM_RINGS - 1)
        centre = arm_frame(s)[0]
        bump = math.sin(math.pi * min(max((s - 0.2) / 0.6, 0.0), 1.0)) ** 2
        for j in range(ARM_SEGMENTS):
            v = i * ARM_SEGMENTS + j
            a = 2.0 * math.pi * j / ARM_SEGMENTS
            up = max(math.cos(a), 0.0) ** 2
            co = flex.data[v].co
            flex.data[v].co = co + (co - centre) * (0.6 * bump * up)
    flex.value = 0.25


def arm(out, name, morph):
    clear_scene()
    obj = link(bpy.data.objects.new("Arm", arm_mesh("Arm")))
    rig = arm_rig()
    skin_to(obj, rig, 4)
    if morph:
        flex_key(obj)
    actions = [wave(rig)]
    finish_skinned(out, name, obj, rig, actions, {"Wave": [7, 13, 20]}, sampled=True)


# --- the humanoid --------------------------------------------------------------

# The figure's stick skeleton in Blender axes (Z up, facing -Y), T pose, and
# the Skin modifier's radii at each joint.
HUMANOID_JOINTS = {
    "hips": ((0.0, 0.0, 0.95), (0.16, 0.11)),
    "spine": ((0.0, 0.0, 1.10), (0.14, 0.10)),
    "chest": ((0.0, 0.0, 1.28), (0.17, 0.11)),
    "upper_chest": ((0.0, 0.0, 1.45), (0.15, 0.09)),
    "neck": ((0.0, 0.0, 1.52), (0.05, 0.05)),
    "head": ((0.0, 0.0, 1.62), (0.09, 0.10)),
    "head_top": ((0.0, 0.0, 1.84), (0.06, 0.07)),
}
for side, sign in (("L", 1.0), ("R", -1.0)):
    HUMANOID_JOINTS.update({
        f"shoulder_{side}": ((sign * 0.20, 0.0, 1.45), (0.06, 0.06)),
        f"elbow_{side}": ((sign * 0.47, 0.0, 1.45), (0.045, 0.045)),
        f"wrist_{side}": ((sign * 0.72, 0.0, 1.45), (0.035, 0.025)),
        f"hand_tip_{side}": ((sign * 0.88, 0.0, 1.45), (0.04, 0.015)),
        f"thigh_{side}": ((sign * 0.10, 0.0, 0.88), (0.08, 0.08)),
        f"knee_{side}": ((sign * 0.10, 0.0, 0.50), (0.055, 0.055)),
        f"ankle_{side}": ((sign * 0.10, 0.0, 0.08), (0.04, 0.04)),
        f"toe_{side}": ((sign * 0.10, -0.16, 0.03), (0.04, 0.02)),
    })
HUMANOID_EDGES = [("hips", "spine"), ("spine", "chest"), ("chest", "upper_chest"),
                  ("upper_chest", "neck"), ("neck", "head"), ("head", "head_top")]
for side in ("L", "R"):
    HUMANOID_EDGES += [("upper_chest", f"shoulder_{side}"), (f"shoulder_{side}", f"elbow_{side}"),
                       (f"elbow_{side}", f"wrist_{side}"), (f"wrist_{side}", f"hand_tip_{side}"),
                       ("hips", f"thigh_{side}"), (f"thigh_{side}", f"knee_{side}"),
                       (f"knee_{side}", f"ankle_{side}"), (f"ankle_{side}", f"toe_{side}")]


def humanoid_bones():
    j = {name: at for name, (at, _) in HUMANOID_JOINTS.items()}
    bones = [("Hips", j["hips"], j["spine"], None, False),
             ("Spine", j["spine"], j["chest"], "Hips", True),
             ("Chest", j["chest"], j["neck"], "Spine", True),
             ("Neck", j["neck"], j["head"], "Chest", True),
             ("Head", j["head"], j["head_top"], "Neck", True)]
    for s in ("L", "R"):
        bones += [(f"Shoulder.{s}", j["upper_chest"], j[f"shoulder_{s}"], "Chest", False),
                  (f"UpperArm.{s}", j[f"shoulder_{s}"], j[f"elbow_{s}"], f"Shoulder.{s}", True),
                  (f"Forearm.{s}", j[f"elbow_{s}"], j[f"wrist_{s}"], f"UpperArm.{s}", True),
                  (f"Hand.{s}", j[f"wrist_{s}"], j[f"hand_tip_{s}"], f"Forearm.{s}", True),
                  (f"Thigh.{s}", j[f"thigh_{s}"], j[f"knee_{s}"], "Hips", False),
                  (f"Shin.{s}", j[f"knee_{s}"], j[f"ankle_{s}"], f"Thigh.{s}", True),
                  (f"Foot.{s}", j[f"ankle_{s}"], j[f"toe_{s}"], f"Shin.{s}", True)]
    return bones


def humanoid_mesh(cuts):
    names = list(HUMANOID_JOINTS)
    index = {n: i for i, n in enumerate(names)}
    mesh = bpy.data.meshes.new("Body")
    mesh.from_pydata([HUMANOID_JOINTS[n][0] for n in names],
                     [(index[a], index[b]) for a, b in HUMANOID_EDGES], [])
    obj = link(bpy.data.objects.new("Body", mesh))
    select_only(obj)
    skin = obj.modifiers.new("skin", "SKIN")
    skin.use_smooth_shade = True
    mesh.skin_vertices[0].data[index["hips"]].use_root = True
    for n in names:
        mesh.skin_vertices[0].data[index[n]].radius = HUMANOID_JOINTS[n][1]
    if cuts:
        # More rings along every limb (the radii interpolated): a denser body.
        bm = bmesh.new()
        bm.from_mesh(mesh)
        bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=cuts)
        bm.to_mesh(mesh)
        bm.free()
    bpy.ops.object.modifier_apply(modifier=skin.name)
    sub = obj.modifiers.new("subdivision", "SUBSURF")
    sub.levels = sub.render_levels = 3
    bpy.ops.object.modifier_apply(modifier=sub.name)
    # The Skin modifier leaves a few vertices without an edge; glTF would drop them.
    bm = bmesh.new()
    bm.from_mesh(mesh)
    bmesh.ops.delete(bm, geom=[v for v in bm.verts if not v.link_edges], context="VERTS")
    bm.to_mesh(mesh)
    bm.free()
    for p in mesh.polygons:
        p.use_smooth = True
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(angle_limit=1.15, island_margin=0.01)
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.seams_from_islands()
    bpy.ops.object.mode_set(mode="OBJECT")
    return obj


def turn(rig, bone, *rotations):
    """The pose rotation of bone that turns it by rotations ((axis, degrees),
    the last applied first) about axes of the armature's space at rest."""
    rest = rig.data.bones[bone].matrix_local.to_quaternion()
    q = mathutils.Quaternion()
    for axis, degrees in rotations:
        q = q @ quat(axis, degrees)
    return rest.inverted() @ q @ rest


def rotation(rig, bone, *rotations):
    return {"rotation_quaternion": turn(rig, bone, *rotations)}


def walk(rig):
    """Legs and arms swing in opposition, knees and elbows bend, the hips bob
    and twist, the head breathes."""
    action = new_action(rig, "Walk")
    for frame, phase in ((1, 0.0), (7, 1.0), (13, 0.0), (19, -1.0), (25, 0.0)):
        key_pose(rig, frame, {
            "Hips": {"location": (0.0, 0.03 * abs(phase), 0.0),
                     **rotation(rig, "Hips", ((0, 0, 1), 6.0 * phase))},
            "Spine": rotation(rig, "Spine", ((0, 0, 1), -4.0 * phase)),
            "Head": {"scale": (1.0 + 0.05 * abs(phase),) * 3},
            "Thigh.L": rotation(rig, "Thigh.L", ((1, 0, 0), -35.0 * phase)),
            "Thigh.R": rotation(rig, "Thigh.R", ((1, 0, 0), 35.0 * phase)),
            "Shin.L": rotation(rig, "Shin.L", ((1, 0, 0), 5.0 + 40.0 * max(phase, 0.0))),
            "Shin.R": rotation(rig, "Shin.R", ((1, 0, 0), 5.0 + 40.0 * max(-phase, 0.0))),
            # Down from the T pose (about Y), then swinging (about X).
            "UpperArm.L": rotation(rig, "UpperArm.L", ((1, 0, 0), 25.0 * phase),
                                   ((0, 1, 0), 70.0)),
            "UpperArm.R": rotation(rig, "UpperArm.R", ((1, 0, 0), -25.0 * phase),
                                   ((0, 1, 0), -70.0)),
            "Forearm.L": rotation(rig, "Forearm.L", ((0, 0, 1), -30.0 - 20.0 * phase)),
            "Forearm.R": rotation(rig, "Forearm.R", ((0, 0, 1), 30.0 - 20.0 * phase)),
        })
    set_interpolation(action, "LINEAR")
    return action


def hold(rig):
    """Three held poses: the head turns, the left hand flaps, the right elbow bends."""
    action = new_action(rig, "Hold")
    for frame, t in ((1, 0.0), (7, 1.0), (13, -0.5)):
        key_pose(rig, frame, {
            "Neck": rotation(rig, "Neck", ((0, 0, 1), 25.0 * t)),
            "Hand.L": rotation(rig, "Hand.L", ((0, 0, 1), -40.0 * t)),
            "Forearm.R": rotation(rig, "Forearm.R", ((0, 0, 1), 60.0 * abs(t))),
        })
    set_interpolation(action, "CONSTANT")
    return action


def sway(rig):
    """The body leans side to side and forward, a shoulder shrugs, the head
    stretches."""
    action = new_action(rig, "Sway")
    for frame, lean in ((1, 0.0), (9, 1.0), (17, -0.6), (25, 0.0)):
        key_pose(rig, frame, {
            "Hips": {"location": (0.04 * lean, 0.0, 0.0)},
            "Spine": rotation(rig, "Spine", ((0, 1, 0), 15.0 * lean), ((0, 0, 1), 5.0 * lean)),
            "Chest": rotation(rig, "Chest", ((1, 0, 0), -12.0 * lean)),
            "Shoulder.L": rotation(rig, "Shoulder.L", ((0, 1, 0), -20.0 * lean)),
            "Head": {"scale": (1.0 + 0.08 * lean, 1.0, 1.0 - 0.04 * lean)},
        })
    third_handles(action)
    return action


def humanoid(out, name="humanoid", cuts=0):
    clear_scene()
    obj = humanoid_mesh(cuts)
    rig = armature_object("HumanRig", humanoid_bones())
    skin_to(obj, rig, 4)
    # The rig (and its child, the body) stands moved and turned in the scene.
    rig.location = (0.4, -0.3, 0.05)
    rig.rotation_euler = (0.0, 0.0, math.radians(30.0))
    bpy.context.view_layer.update()
    actions = [walk(rig), hold(rig), sway(rig)]
    frames = {"Walk": [4, 7, 16], "Hold": [10, 13], "Sway": [4, 12, 22]}
    finish_skinned(out, name, obj, rig, actions, frames, sampled=False)


# --- static assets -------------------------------------------------------------

def prop(out):
    clear_scene()
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    obj.name = obj.data.name = "Prop"
    sub = obj.modifiers.new("subdivision", "SUBSURF")
    sub.levels = sub.render_levels = 1
    bpy.ops.object.modifier_apply(modifier=sub.name)
    for p in obj.data.polygons:
        p.use_smooth = True
    mark_uv_seams(obj.data)
    export_gltf(f"{out}/prop.glb", sampled=True)
    export_fbx(f"{out}/prop.fbx")


def shapekey(out):
    clear_scene()
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    obj = bpy.context.active_object
    obj.name = obj.data.name = "Block"
    sub = obj.modifiers.new("subdivision", "SUBSURF")
    sub.levels = sub.render_levels = 3
    bpy.ops.object.modifier_apply(modifier=sub.name)
    for p in obj.data.polygons:
        p.use_smooth = True
    mark_uv_seams(obj.data)
    obj.shape_key_add(name="Basis", from_mix=False)
    bulge = obj.shape_key_add(name="Bulge", from_mix=False)
    pinch = obj.shape_key_add(name="Pinch", from_mix=False)
    for point in bulge.data:
        point.co *= 1.0 + 0.3 * max(0.0, point.co.z + 0.2)
    for point in pinch.data:
        point.co.x *= 1.0 - 0.5 * (0.5 - abs(point.co.z))
    bulge.value = 0.0
    pinch.value = 0.3
    export_gltf(f"{out}/shapekey.glb", sampled=True)
    export_fbx(f"{out}/shapekey.fbx")


# --- export and Blender's evaluated mesh -------------------------------------

def gltf_axes(points):
    return np.stack([points[:, 0], points[:, 2], -points[:, 1]], axis=1)


def world_positions(obj, mesh):
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3).astype(np.float64)
    m = np.array(obj.matrix_world, dtype=np.float64)
    return gltf_axes(co @ m[:3, :3].T + m[:3, 3])


def evaluated_positions(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        if len(mesh.vertices) != len(obj.data.vertices):
            sys.exit(f"{obj.name}: the evaluated mesh has {len(mesh.vertices)} vertices, "
                     f"the mesh {len(obj.data.vertices)}")
        return world_positions(evaluated, mesh)
    finally:
        evaluated.to_mesh_clear()


def rounded(points):
    # float32 precision is what the exporter writes; 9 digits keep it.
    return [[float(f"{c:.9g}") for c in p] for p in points]


def frames_json(obj, rig, actions, frames):
    scene = bpy.context.scene
    record = {
        "mesh": obj.name,
        "armature": rig.name,
        "fps": FPS,
        "bones": [b.name for b in rig.data.bones],
        "vertex_count": len(obj.data.vertices),
        "axes": "glTF: Blender's (x, y, z) written as (x, z, -y)",
        "rest_positions": rounded(world_positions(obj, obj.data)),
        "frames": [],
    }
    for action in actions:
        reset_pose(rig)
        rig.animation_data.action = action
        for frame in frames[action.name]:
            scene.frame_set(frame)
            record["frames"].append({
                "animation": action.name,
                "frame": frame,
                "time_seconds": float(np.float32(frame / FPS)),
                "positions": rounded(evaluated_positions(obj)),
            })
    return record


def finish_skinned(out, name, obj, rig, actions, frames, sampled):
    scene = bpy.context.scene
    start = min(int(a.frame_range[0]) for a in actions)
    end = max(int(a.frame_range[1]) for a in actions)
    scene.frame_start, scene.frame_end = start, end
    record = frames_json(obj, rig, actions, frames)
    with open(f"{out}/{name}.frames.json", "w") as f:
        json.dump(record, f, separators=(",", ":"))
    # Exported as an artist leaves the scene: the first action active, first frame.
    reset_pose(rig)
    rig.animation_data.action = actions[0]
    scene.frame_set(start)
    export_gltf(f"{out}/{name}.glb", sampled=sampled)
    export_fbx(f"{out}/{name}.fbx")


def export_gltf(path, sampled):
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB", export_yup=True,
                              export_animations=True, export_skins=True, export_morph=True,
                              export_force_sampling=sampled)


def export_fbx(path):
    from io_scene_fbx import export_fbx_bin
    header = export_fbx_bin.fbx_header_elements

    def pinned(root, scene_data, time=None):
        header(root, scene_data, datetime.datetime(2020, 1, 1))

    export_fbx_bin.fbx_header_elements = pinned
    try:
        bpy.ops.export_scene.fbx(filepath=path)
    finally:
        export_fbx_bin.fbx_header_elements = header


def main():
    out = args()
    arm(out, "arm", morph=False)
    arm(out, "arm-morph", morph=True)
    humanoid(out)
    humanoid(out, "humanoid-20k", cuts=2)
    prop(out)
    shapekey(out)
    print("make_rigged_assets: wrote the assets into", out)


main()
