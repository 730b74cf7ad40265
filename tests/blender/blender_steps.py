"""What a user does, as the scripts that run inside Blender do it
(blender_checks.py, modal_ui_checks.py, skinned_checks.py): vertices selected in order in Edit
Mode, and the modal Dualform Drag's window-free steps driven by synthetic
events on a stand-in for the operator (a 3D view's mouse mapping needs a
window, so the mouse maps linearly to a translation: 1024 pixels a unit)."""

import time
import types

import bmesh
import bpy
import numpy as np


def select_in_order(obj, vertices) -> None:
    """``obj`` active in Edit Mode with exactly ``vertices`` selected, in
    that order (Blender's selection history)."""
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    select_vertices(obj, vertices)


def select_vertices(obj, vertices) -> None:
    """Exactly ``vertices`` selected, in that order, in ``obj``'s edit mesh."""
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    for v in bm.verts:
        v.select = False
    bm.select_history.clear()
    for i in vertices:
        bm.verts[i].select = True
        bm.select_history.add(bm.verts[i])
    bmesh.update_edit_mesh(obj.data)


class LinearMapping:
    """Mouse pixels to a translation along two of the object's axes."""

    def __init__(self, axes=(0, 1)) -> None:
        self.axes = axes

    def translation(self, start, now):
        out = np.zeros(3)
        out[self.axes[0]] = (now[0] - start[0]) / 1024.0
        out[self.axes[1]] = (now[1] - start[1]) / 1024.0
        return out

    def view_axis(self):
        return np.array([0.0, 0.0, 1.0])

    def angle(self, start, now):
        return 0.0


def drag_stand_in(obj, mapping=None, **properties):
    """Dualform Drag started on ``obj`` with the operator's ``properties``
    (keep, key_name, driver), its steps bound to a stand-in."""
    from dualform_blender import operators

    settings = dict(keep="MESH", key_name="", driver=False)
    settings.update(properties)
    driver = types.SimpleNamespace(bl_label="Dualform Drag",
                                   report=lambda kind, text: print(kind, text), **settings)
    op = operators.DUALFORM_OT_drag
    for name in ("start", "modal", "_end", "_motion", "_header", "_restore_mode"):
        setattr(driver, name, getattr(op, name).__get__(driver))
    bpy.context.view_layer.objects.active = obj
    assert driver.start(bpy.context, obj)
    driver.mapping = mapping or LinearMapping()
    driver.mouse_start = (0, 0)
    return driver


def event(kind, x=0, y=0, value="NOTHING"):
    return types.SimpleNamespace(type=kind, value=value, mouse_region_x=x, mouse_region_y=y)


def run_timer_until(driver, done, limit=30.0):
    """Timer ticks until ``done(state)``; the state it returned then."""
    end = time.monotonic() + limit
    while time.monotonic() < end:
        state = driver.modal(bpy.context, event("TIMER"))
        if done(state):
            return state
        time.sleep(0.005)
    raise RuntimeError("the drag did not settle")
