"""Takes the add-on's pictures for docs/blender.md: Blender with the add-on
enabled and the sidebar's Dualform tab open, after an edit.

- From the cow (a PLY), docs/figures/blender-addon.png: the front leg
  Water-Filled (its ROI selected in Edit Mode) after a Dualform Deform into
  the shape key "Step".
- From the rigged arm of tests/skin (arm.glb, the fixture rigged_assets),
  docs/figures/blender-corrective.png: the arm at frame 13 of its action
  "Wave", its hand Water-Filled on the posed surface and lifted, kept by
  Bake Corrective as the shape key "Hand Lift" driven by the elbow's angle.

xvfb-run -s "-screen 0 1600x1000x24" blender --factory-startup \
    --enable-event-simulate --window-geometry 0 0 1600 1000 \
    --python samples/blender/screenshot.py -- ADDON.zip MODEL OUT.png

(ADDON.zip from samples/blender/package.py; MODEL: the cow saved as PLY,
or arm.glb; relative paths start from the current folder.) The sidebar's
tab is switched as a user would, by a (simulated) click on it, since
Blender 3.4 has no property for the active tab. Any failure prints its
traceback and ends Blender with exit status 1 (an error in a timer would
otherwise leave it running).
"""

import os
import sys
import traceback

import bmesh
import bpy
from mathutils import Euler, Vector

# Blender 3.4's add-on installer fails on a relative path.
zip_path, model_path, out_png = map(os.path.abspath, sys.argv[sys.argv.index("--") + 1:])


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == "VIEW_3D":
            regions = {r.type: r for r in area.regions}
            return window, area, regions["WINDOW"], regions["UI"]
    raise RuntimeError("no 3D view")


def select(obj, vertices) -> None:
    """Exactly ``vertices`` selected, in order, in Edit Mode."""
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    for v in bm.verts:
        v.select = False
    bm.select_history.clear()
    for i in vertices:
        bm.verts[i].select = True
        bm.select_history.add(bm.verts[i])
    bm.select_flush(True)
    bmesh.update_edit_mesh(obj.data)


def edit(obj, first, last, ball_center, settings) -> None:
    """Water-Fill from first to last, a handle of the 0.03 ball around
    ``ball_center`` (on the surface as shown), the panel's Deform (or Bake
    Corrective) button with ``settings``, then the ROI selected."""
    from dualform_blender import bridge

    bpy.ops.object.mode_set(mode="EDIT")
    select(obj, [first, last])
    bpy.ops.dualform.water_fill_roi()
    bpy.ops.object.mode_set(mode="OBJECT")
    roi = bridge.group_vertices(obj, bridge.ROI_GROUP).tolist()
    with bridge.Surface.as_shown(obj) as surface, \
            surface.mesh.roi_ball(ball_center, 0.03) as ball:
        grip = surface.copies(ball.vertices()).tolist()
    bpy.ops.object.mode_set(mode="EDIT")
    select(obj, grip)
    bpy.ops.dualform.add_handle()
    panel = bpy.context.scene.dualform
    for name, value in settings.items():
        setattr(panel, name, value)
    bpy.ops.dualform.deform(translate=panel.translate, keep=panel.keep,
                            key_name=panel.key_name, driver=panel.driver)
    select(obj, roi)


def cow_scene():
    bpy.ops.import_mesh.ply(filepath=model_path)
    cow = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = cow
    # The model's up is +y; Blender's is +z (the edit works in the mesh's
    # own space either way).
    cow.rotation_euler = (1.5707963, 0.0, 0.0)
    edit(cow, 771, 681, 771, {"translate": (0.09, 0.03, 0.0), "key_name": "Step"})
    return (1.35, 0.0, 0.75), (0.05, 0.0, 0.0), 1.9


def arm_scene():
    import numpy

    # Debian 12's numpy 1.24 dropped numpy.bool, which Blender 3.4's glTF
    # importer still uses (docs/blender.md).
    numpy.bool = bool
    bpy.ops.import_scene.gltf(filepath=model_path)
    arm = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    rig = next(o for o in bpy.context.scene.objects if o.type == "ARMATURE")
    rig.animation_data.action = next(a for a in bpy.data.actions if a.name.startswith("Wave"))
    bpy.context.scene.frame_set(13)
    bpy.context.view_layer.objects.active = arm
    # Edit Mode shows (and selects on) the posed mesh.
    modifier = next(m for m in arm.modifiers if m.type == "ARMATURE")
    modifier.show_in_editmode = modifier.show_on_cage = True
    from dualform_blender import bridge

    with bridge.Surface.as_shown(arm) as surface:
        shown = surface.shown
    # The hand: the vertex farthest from the posed arm's centroid; the
    # region ends a quarter of the way back.
    centroid = shown.mean(axis=0)
    tip = int(((shown - centroid) ** 2).sum(axis=1).argmax())
    toward = shown[tip] + (centroid - shown[tip]) / 4.0
    end = int(((shown - toward) ** 2).sum(axis=1).argmin())
    edit(arm, tip, end, tip, {"translate": (0.0, 0.0, 0.12), "keep": "CORRECTIVE",
                              "key_name": "Hand Lift", "driver": True})
    world = arm.matrix_world
    middle = world @ Vector(tuple(float(c) for c in (shown.max(axis=0) + shown.min(axis=0)) / 2))
    return (1.25, 0.0, 0.35), tuple(middle), 3.2


def prepare():
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    bpy.ops.preferences.addon_enable(module="dualform_blender")
    for o in list(bpy.data.objects):
        if o.type == "MESH":
            bpy.data.objects.remove(o)
    window, area, region, ui = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        scene = arm_scene if model_path.endswith(".glb") else cow_scene
        rotation, location, distance = scene()
        space = area.spaces.active
        space.show_region_ui = True
        space.shading.type = "SOLID"
        rv3d = space.region_3d
        rv3d.view_perspective = "PERSP"
        rv3d.view_rotation = Euler(rotation).to_quaternion()
        rv3d.view_location = location
        rv3d.view_distance = distance
    return 1.0


state = {"step": 0}


def take_step():
    window, area, region, ui = view3d()
    if state["step"] == 0:
        state["step"] = 1
        # Closes the splash screen.
        x, y = region.x + 40, region.y + 40
        window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        window.event_simulate(type="ESC", value="PRESS", x=x, y=y)
        window.event_simulate(type="ESC", value="RELEASE", x=x, y=y)
        return prepare()
    if state["step"] == 1:
        state["step"] = 2
        # A click on the fourth tab (Item, Tool, View, Dualform) of the
        # sidebar's strip, at its right edge: 172 pixels below its top at
        # the default scale.
        x, y = ui.x + ui.width - 10, ui.y + ui.height - 172
        print("screenshot: clicking the tab at", x, y, "sidebar", ui.x, ui.y, ui.width, ui.height)
        window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        window.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
        window.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
        return 1.0
    with bpy.context.temp_override(window=window):
        bpy.ops.screen.screenshot(filepath=out_png)
    bpy.ops.wm.quit_blender()
    return None


def step():
    try:
        return take_step()
    except Exception:
        traceback.print_exc()
        sys.stdout.flush()
        os._exit(1)


bpy.app.timers.register(step, first_interval=1.0)
