"""Runs inside headless Blender (tests/blender/test_skinned.py starts it, in
the folder that holds dualform_blender.zip): installs the add-on as
docs/blender.md says, imports the rigged glTF assets of tests/skin (a bent
arm, the arm with the shape key "Flex" at 0.25 under its armature, a
19-bone humanoid) as an artist would, poses each at a frame of its action,
edits the posed mesh with the add-on's operators and bakes the edit as a
corrective shape key; writes what Blender itself evaluates, and the same
edit made by the dualform package on a static copy of Blender's posed mesh,
to OUT/skinned.json for the test to compare.

blender -b --factory-startup --python-exit-code 1 --python skinned_checks.py --
    ASSETS_DIR OUT

For each asset (object space throughout; the static copy is Blender's own
evaluated mesh):
1. the add-on's skin, posed by the library, against Blender's evaluated mesh;
2. Water-Fill ROI from two vertices selected in order, against the
   package's Water-Filling of the static copy (and of the rest mesh);
3. a ROI and a handle group (balls around the vertex farthest from the
   centroid, chosen on the static copy), Active Group as ROI and as Handle;
4. Dualform Deform lifting the handle, kept as the corrective key
   "Corrective" with its driver; Blender's evaluated mesh against the
   static edit, with the key at its driven value, muted, and holding the
   naive corrective (the posed displacement copied into rest space);
5. the driver's value at every frame of the action, against the bone's
   angle over its angle at this frame.
Then, on the arm: the modal drag's steps on the posed mesh (each shown
frame is Blender's evaluated mesh; Enter bakes; Escape restores), the edit
kept in the mesh, and Preserve Volume refused.
"""

import json
import math
import os
import sys
from pathlib import Path

import bpy
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_arrays import key_positions, mesh_positions  # noqa: E402
from blender_steps import (LinearMapping, drag_stand_in, event, run_timer_until,  # noqa: E402
                           select_in_order)
from documented_install import install_as_documented  # noqa: E402

np = numpy
# Debian 12's numpy 1.24 dropped numpy.bool, which Blender 3.4's glTF
# importer still uses: a packaging mismatch (docs/blender.md), patched here.
numpy.bool = bool

assets_dir, out_dir = (Path(a) for a in sys.argv[sys.argv.index("--") + 1:])
ASSETS = ("arm", "arm-morph", "humanoid")
LIFT = np.array([0.0, 0.04, 0.03])  # of the diagonal, in object space
KEY = "Corrective"

install_as_documented()
import dualform as dfm  # noqa: E402  (importable once the add-on is enabled)
from dualform_blender import bridge  # noqa: E402


def clear_scene():
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.armatures,
                       bpy.data.actions, bpy.data.shape_keys):
        for block in list(collection):
            if collection is bpy.data.shape_keys:
                continue  # freed with their meshes
            collection.remove(block)


def evaluated(obj) -> np.ndarray:
    """Blender's evaluated mesh (shape keys, then the Armature modifier),
    object space, float64."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    mesh = obj.evaluated_get(depsgraph).to_mesh()
    out = mesh_positions(mesh).astype(np.float64)
    obj.evaluated_get(depsgraph).to_mesh_clear()
    return out


def make_group(obj, name, vertices) -> None:
    group = obj.vertex_groups.new(name=name)
    group.add([int(v) for v in vertices], 1.0, "REPLACE")
    obj.vertex_groups.active_index = group.index


def import_posed(name):
    """The asset imported, its action playing on the armature, at the
    middle frame Blender's fixture evaluated: (mesh object, armature, frame)."""
    clear_scene()
    bpy.ops.import_scene.gltf(filepath=str(assets_dir / f"{name}.glb"))
    record = json.loads((assets_dir / f"{name}.frames.json").read_text())
    frame = record["frames"][len(record["frames"]) // 2]
    mesh = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    armature = next(o for o in bpy.context.scene.objects if o.type == "ARMATURE")
    action = next(a for a in bpy.data.actions if a.name.startswith(frame["animation"] + "_"))
    armature.animation_data.action = action
    bpy.context.scene.frame_set(frame["frame"])
    bpy.context.view_layer.objects.active = mesh
    for o in bpy.context.scene.objects:
        o.select_set(o == mesh)
    return mesh, armature, frame


def static_edit(shown, triangles, roi, grip, lift):
    """The package's edit of a static copy of the shown mesh: the ROI and
    handle as given, the handle lifted."""
    with dfm.Context() as ctx, \
            dfm.Mesh.from_arrays(ctx, shown, triangles, weld=0) as mesh, \
            mesh.roi_from_vertices(roi) as region, \
            dfm.Session(mesh, region, [np.unique(mesh.surface_map()[grip])]) as session:
        session.set_translation(0, lift)
        session.solve()
        return session.read_positions()[0]


def relative(a, b, diagonal) -> float:
    return float(np.linalg.norm(a - b, axis=1).max() / diagonal)


def check_asset(name):
    obj, armature, frame = import_posed(name)
    r = {"frame": frame["frame"], "animation": frame["animation"]}
    keys_before = ({k.name: k.value for k in obj.data.shape_keys.key_blocks}
                   if obj.data.shape_keys else {})
    shown = evaluated(obj)
    rest = mesh_positions(obj.data).astype(np.float64)
    diagonal = float(np.linalg.norm(shown.max(axis=0) - shown.min(axis=0)))
    r["diagonal"] = diagonal
    r["pose_moves"] = relative(shown, rest, diagonal)
    triangles = bridge.mesh_arrays(obj.data)[1]

    # 1. the add-on's skin against Blender's armature
    with bridge.Surface.as_shown(obj) as surface:
        r["skin_error"] = relative(surface.shown, shown, diagonal)
        r["joints"] = len(surface.skin.bones)
        r["unweighted_joint"] = "" in surface.skin.bones

    # 2. Water-Fill on the posed surface: from the vertex farthest from the
    # centroid to the one nearest a third of the way back to it
    tip = int(np.argmax(np.linalg.norm(shown - shown.mean(axis=0), axis=1)))
    toward = shown[tip] + (shown.mean(axis=0) - shown[tip]) / 3.0
    end = int(np.argmin(np.linalg.norm(shown - toward, axis=1)))
    select_in_order(obj, [tip, end])
    r["water_fill"] = list(bpy.ops.dualform.water_fill_roi())
    bpy.ops.object.mode_set(mode="OBJECT")
    filled = bridge.group_vertices(obj, bridge.ROI_GROUP)
    with dfm.Context() as ctx:
        for what, positions in (("static", shown), ("rest", rest)):
            with dfm.Mesh.from_arrays(ctx, positions, triangles, weld=0) as mesh, \
                    mesh.water_fill(tip, end) as roi:
                lowest = mesh.surface_map()
                region = np.flatnonzero(np.isin(lowest, roi.vertices()))
                r[f"water_fill_{what}"] = bool(np.array_equal(filled, region))
        # 3. the edit's ROI and handle, chosen on the static copy
        with dfm.Mesh.from_arrays(ctx, shown, triangles, weld=0) as mesh, \
                mesh.roi_ball(tip, 0.2) as roi, mesh.roi_ball(tip, 0.03) as ball:
            lowest = mesh.surface_map()
            region = np.flatnonzero(np.isin(lowest, roi.vertices()))
            grip = np.flatnonzero(np.isin(lowest, ball.vertices()))
    make_group(obj, "Edit Region", region)
    r["group_as_roi"] = list(bpy.ops.dualform.group_as_roi())
    make_group(obj, "Grip", grip)
    r["group_as_handle"] = list(bpy.ops.dualform.group_as_handle())

    # 4. the corrective
    lift = LIFT * diagonal
    r["deform"] = list(bpy.ops.dualform.deform(translate=tuple(lift), keep="CORRECTIVE",
                                               key_name=KEY, driver=True))
    expected = static_edit(shown, triangles, region, grip, lift)
    r["edit_moves"] = relative(expected, shown, diagonal)
    bpy.context.scene.frame_set(frame["frame"])
    key = obj.data.shape_keys.key_blocks[KEY]
    r["driven_value"] = key.value
    corrected = evaluated(obj)
    r["corrective_error"] = relative(corrected, expected, diagonal)
    r["outside_roi_moved"] = float(np.abs(np.delete(corrected - shown, region, axis=0)).max())
    r["keys_after"] = {k.name: k.value for k in obj.data.shape_keys.key_blocks}
    r["keys_before"] = keys_before
    key.mute = True
    r["muted_error"] = relative(evaluated(obj), shown, diagonal)
    key.mute = False
    stored = key_positions(obj, KEY)
    basis = key_positions(obj, obj.data.shape_keys.reference_key.name).astype(np.float64)
    key.data.foreach_set("co", (basis + (expected - shown)).astype(np.float32).reshape(-1))
    obj.data.update()
    r["naive_error"] = relative(evaluated(obj), expected, diagonal)
    key.data.foreach_set("co", stored.reshape(-1))
    obj.data.update()
    r["restored_error"] = relative(evaluated(obj), corrected, diagonal)

    # 5. the driver
    curve = obj.data.shape_keys.animation_data.drivers.find(f'key_blocks["{KEY}"].value')
    driver = curve.driver
    target = driver.variables[0].targets[0]
    r["driver"] = {"simple": driver.is_simple_expression, "valid": driver.is_valid,
                   "bone": target.bone_target, "armature": target.id.name,
                   "space": target.transform_space, "channel": target.transform_type}
    bone = armature.pose.bones[target.bone_target]

    def bone_angle():
        local = armature.convert_space(pose_bone=bone, matrix=bone.matrix, from_space="POSE",
                                       to_space="LOCAL")
        return 2.0 * math.acos(min(abs(local.to_quaternion().normalized().w), 1.0))

    baked_angle = bone_angle()
    first, last = (int(f) for f in armature.animation_data.action.frame_range)
    r["driven"] = []
    for f in range(first, last + 1):
        bpy.context.scene.frame_set(f)
        r["driven"].append([f, key.value, min(max(bone_angle() / baked_angle, 0.0), 1.0)])
    bpy.context.scene.frame_set(frame["frame"])
    return r


def check_arm_extras(results):
    """On the arm (ROI and handle as check_asset left them): the modal drag,
    the edit kept in the mesh, Preserve Volume."""
    obj = bpy.data.objects["Arm"]
    r = {}
    obj.shape_key_clear()
    shown = evaluated(obj)
    diagonal = float(np.linalg.norm(shown.max(axis=0) - shown.min(axis=0)))
    before = mesh_positions(obj.data).tobytes()
    # Escape: moved while dragging, then everything back bit for bit.
    drag = drag_stand_in(obj, LinearMapping(axes=(1, 2)), keep="CORRECTIVE", key_name=KEY,
                         driver=True)
    drag.modal(bpy.context, event("MOUSEMOVE", 60, 40))
    run_timer_until(drag, lambda s: drag.drag.applied > 0)
    # What Blender shows of the preview is the session's frame.
    frame_shown, _ = drag.drag.session.read_positions()
    r["preview_error"] = relative(evaluated(obj), frame_shown, diagonal)
    r["escape_moved"] = relative(evaluated(obj), shown, diagonal)
    r["escape"] = list(drag.modal(bpy.context, event("ESC", value="PRESS")))
    r["escape_restored"] = (mesh_positions(obj.data).tobytes() == before
                            and obj.data.shape_keys is None)
    # Enter: the newest frame baked into the corrective.
    drag = drag_stand_in(obj, LinearMapping(axes=(1, 2)), keep="CORRECTIVE", key_name=KEY,
                         driver=True)
    for step in range(1, 6):
        drag.modal(bpy.context, event("MOUSEMOVE", 12 * step, 8 * step))
        drag.modal(bpy.context, event("TIMER"))
    drag.modal(bpy.context, event("RET", 60, 40, value="PRESS"))
    session_frame = {}
    original_finish = drag.drag.finish

    def finish_and_keep_the_frame():
        session_frame["positions"] = drag.drag.session.read_positions()[0]
        original_finish()

    drag.drag.finish = finish_and_keep_the_frame
    r["enter"] = list(run_timer_until(drag, lambda s: s != {"RUNNING_MODAL"}))
    r["enter_error"] = relative(evaluated(obj), session_frame["positions"], diagonal)
    r["enter_moved"] = relative(evaluated(obj), shown, diagonal)
    r["enter_keys"] = [k.name for k in obj.data.shape_keys.key_blocks]
    obj.shape_key_clear()
    # Kept in the mesh (no shape keys): the mesh's vertices are the rest
    # shape whose pose is the edit.
    lift = tuple(LIFT * diagonal)
    r["deform_mesh"] = list(bpy.ops.dualform.deform(translate=lift, keep="MESH"))
    triangles = bridge.mesh_arrays(obj.data)[1]
    region = bridge.group_vertices(obj, bridge.ROI_GROUP)
    grip = bridge.group_vertices(obj, "Dualform Handle 1")
    r["mesh_error"] = relative(evaluated(obj), static_edit(shown, triangles, region, grip,
                                                           np.array(lift)), diagonal)
    # Preserve Volume (dual quaternions) is refused with the reason.
    modifier = next(m for m in obj.modifiers if m.type == "ARMATURE")
    modifier.use_deform_preserve_volume = True
    for what, call in (("deform", lambda: bpy.ops.dualform.deform(translate=lift,
                                                                 keep="CORRECTIVE")),
                       ("grow", lambda: bpy.ops.dualform.grow_roi(rings=1))):
        try:
            call()
            r[f"preserve_volume_{what}"] = "accepted"
        except RuntimeError as error:  # the operator's ERROR report
            r[f"preserve_volume_{what}"] = str(error)
    modifier.use_deform_preserve_volume = False
    results["arm_extras"] = r


results = {}
for asset in ASSETS:
    results[asset] = check_asset(asset)
    if asset == "arm":
        check_arm_extras(results)
(out_dir / "skinned.json").write_text(json.dumps(results, indent=1))
print("skinned_checks: done")
