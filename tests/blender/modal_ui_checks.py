"""Runs inside Blender with a window (under Xvfb, --enable-event-simulate),
in the folder that holds dualform_blender.zip: the modal Dualform Drag
invoked in the 3D view and driven by simulated mouse and keyboard events,
as a user drives it. Writes OUT/modal_ui.json.

xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup
    --enable-event-simulate --window-geometry 0 0 1280 800
    --python modal_ui_checks.py -- PLY OUT HOOF_FILE
"""

import json
import os
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_arrays import positions  # noqa: E402
from blender_steps import select_vertices  # noqa: E402
from documented_install import install_as_documented  # noqa: E402

ply_path, out_dir, hoof_file = sys.argv[sys.argv.index("--") + 1:]
hoof = [int(v) for v in Path(hoof_file).read_text().split()]
results = {}
state = {"step": 0}


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == "VIEW_3D":
            region = next(r for r in area.regions if r.type == "WINDOW")
            return window, area, region
    raise RuntimeError("no 3D view")


def prepare(window, area, region):
    install_as_documented()
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    bpy.ops.import_mesh.ply(filepath=ply_path)
    cow = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = cow
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.object.mode_set(mode="EDIT")
        select_vertices(cow, [771, 681])
        bpy.ops.dualform.water_fill_roi()
        select_vertices(cow, hoof)
        bpy.ops.dualform.add_handle()
        bpy.ops.object.mode_set(mode="OBJECT")
        bpy.ops.view3d.view_all()
    state["rest"] = state["original"] = positions(cow).tobytes()
    state["cow"] = cow
    state["name"] = cow.name


# Simulated events are handled after the timer returns, so the mouse is
# moved one step before the drag is invoked where it stands.
def mouse_to_centre(window, region):
    x, y = region.x + region.width // 2, region.y + region.height // 2
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    state["mouse"] = (x, y)


def start_drag(window, area, region):
    with bpy.context.temp_override(window=window, area=area, region=region):
        results.setdefault("invoke", []).append(list(bpy.ops.dualform.drag("INVOKE_DEFAULT")))


def step():
    window, area, region = view3d()
    s = state["step"]
    state["step"] += 1
    cow = state.get("cow")
    if s == 0:
        x, y = region.x + 40, region.y + 40
        window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        window.event_simulate(type="ESC", value="PRESS", x=x, y=y)
        window.event_simulate(type="ESC", value="RELEASE", x=x, y=y)
        prepare(window, area, region)
    elif s in (1, 6):
        mouse_to_centre(window, region)
    elif s in (2, 7):
        start_drag(window, area, region)
    elif s in (3, 8):
        x, y = state["mouse"]
        for k in range(1, 6):
            window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x + 20 * k, y=y + 8 * k)
    elif s == 4:
        x, y = state["mouse"]
        results["moving_while_dragging"] = bool(positions(cow).tobytes() != state["rest"])
        window.event_simulate(type="RET", value="PRESS", x=x + 100, y=y + 40)
        window.event_simulate(type="RET", value="RELEASE", x=x + 100, y=y + 40)
    elif s == 5:
        p = positions(cow)
        rest = np.frombuffer(state["rest"], dtype=np.float32).reshape(-1, 3)
        moved = np.linalg.norm(p - rest, axis=1)
        roi = cow.vertex_groups["Dualform ROI"].index
        inside = [v.index for v in cow.data.vertices if any(g.group == roi for g in v.groups)]
        outside = np.setdiff1d(np.arange(len(p)), inside)
        results["enter_hoof_moved"] = float(moved[771])
        results["enter_outside_moved"] = float(moved[outside].max())
        # The kept drag is one undo step: Ctrl+Z puts the mesh back exactly.
        with bpy.context.temp_override(window=window, area=area, region=region):
            bpy.ops.ed.undo()
        cow = state["cow"] = bpy.data.objects[state["name"]]
        results["enter_undo_restored_bitwise"] = positions(cow).tobytes() == state["original"]
        state["rest"] = positions(cow).tobytes()
    elif s == 9:
        results["escape_moving_while_dragging"] = bool(positions(cow).tobytes() != state["rest"])
        x, y = state["mouse"]
        window.event_simulate(type="ESC", value="PRESS", x=x, y=y)
        window.event_simulate(type="ESC", value="RELEASE", x=x, y=y)
    elif s == 10:
        results["escape_restored_bitwise"] = positions(cow).tobytes() == state["rest"]
        (Path(out_dir) / "modal_ui.json").write_text(json.dumps(results, indent=1))
        bpy.ops.wm.quit_blender()
        return None
    return 0.75


bpy.app.timers.register(step, first_interval=1.0)
