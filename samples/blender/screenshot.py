"""Takes docs/figures/blender-addon.png: Blender with the add-on enabled,
the cow's front leg Water-Filled (its ROI selected in Edit Mode) after a
Dualform Deform into the shape key "Step", and the sidebar's Dualform tab
open.

xvfb-run -s "-screen 0 1600x1000x24" blender --factory-startup \
    --enable-event-simulate --window-geometry 0 0 1600 1000 \
    --python samples/blender/screenshot.py -- ADDON.zip COW.ply OUT.png

(ADDON.zip from samples/blender/package.py; COW.ply: the cow saved as PLY;
relative paths start from the current folder.) The sidebar's tab is
switched as a user would, by a (simulated) click on it, since Blender 3.4
has no property for the active tab. Any failure prints its traceback and
ends Blender with exit status 1 (an error in a timer would otherwise leave
it running).
"""

import os
import sys
import traceback

import bmesh
import bpy

# Blender 3.4's add-on installer fails on a relative path.
zip_path, ply_path, out_png = map(os.path.abspath, sys.argv[sys.argv.index("--") + 1:])


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == "VIEW_3D":
            regions = {r.type: r for r in area.regions}
            return window, area, regions["WINDOW"], regions["UI"]
    raise RuntimeError("no 3D view")


def prepare():
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    bpy.ops.preferences.addon_enable(module="dualform_blender")
    for o in list(bpy.data.objects):
        if o.type == "MESH":
            bpy.data.objects.remove(o)
    bpy.ops.import_mesh.ply(filepath=ply_path)
    cow = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = cow
    # The model's up is +y; Blender's is +z (the edit works in the mesh's
    # own space either way).
    cow.rotation_euler = (1.5707963, 0.0, 0.0)
    window, area, region, ui = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.object.mode_set(mode="EDIT")
        bm = bmesh.from_edit_mesh(cow.data)
        bm.verts.ensure_lookup_table()
        for v in bm.verts:
            v.select = False
        for i in (771, 681):
            bm.verts[i].select = True
            bm.select_history.add(bm.verts[i])
        bmesh.update_edit_mesh(cow.data)
        bpy.ops.dualform.water_fill_roi()
        from dualform_blender import bridge

        bpy.ops.object.mode_set(mode="OBJECT")
        roi = set(bridge.group_vertices(cow, bridge.ROI_GROUP).tolist())
        import dualform as dfm

        with dfm.Context() as ctx, dfm.Mesh.load(ctx, ply_path) as m, m.roi_ball(771, 0.03) as b:
            hoof = b.vertices().tolist()
        bpy.ops.object.mode_set(mode="EDIT")
        bm = bmesh.from_edit_mesh(cow.data)
        bm.verts.ensure_lookup_table()
        for v in bm.verts:
            v.select = v.index in hoof
        bmesh.update_edit_mesh(cow.data)
        bpy.ops.dualform.add_handle()
        # The panel's numbers, and its Deform button.
        settings = bpy.context.scene.dualform
        settings.translate = (0.09, 0.03, 0.0)
        settings.key_name = "Step"
        bpy.ops.dualform.deform(translate=settings.translate, keep=settings.keep,
                                key_name=settings.key_name)
        bm = bmesh.from_edit_mesh(cow.data)
        for v in bm.verts:
            v.select = v.index in roi
        bm.select_flush(True)
        bmesh.update_edit_mesh(cow.data)
        space = area.spaces.active
        space.show_region_ui = True
        space.shading.type = "SOLID"
        rv3d = space.region_3d
        rv3d.view_perspective = "PERSP"
        from mathutils import Euler

        rv3d.view_rotation = Euler((1.35, 0.0, 0.75)).to_quaternion()
        rv3d.view_location = (0.05, 0.0, 0.0)
        rv3d.view_distance = 1.9
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
