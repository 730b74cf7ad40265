"""The add-on's operators: Water-Fill ROI, Add Handle, the modal Dualform
Drag and its non-interactive twin Dualform Deform."""

import math

import bmesh
import bpy
import numpy as np
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty, StringProperty
from mathutils import Vector

from . import bridge

KEEP_ITEMS = [
    ("MESH", "Mesh", "write the result into the mesh"),
    ("SHAPE_KEY", "Shape Key", "keep the mesh and add the result as a shape key (value 1)"),
]


def _library(context) -> str:
    addon = context.preferences.addons.get(__package__)
    return addon.preferences.library_path if addon else ""


def _edit_mesh_object(context):
    obj = context.active_object
    return obj if obj is not None and obj.type == "MESH" and context.mode == "EDIT_MESH" else None


class DUALFORM_OT_water_fill_roi(bpy.types.Operator):
    """Water-Fill from the two selected vertices: first the limb's tip, then
    where the region ends; the region becomes the 'Dualform ROI' group"""

    bl_idname = "dualform.water_fill_roi"
    bl_label = "Water-Fill ROI"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _edit_mesh_object(context) is not None

    def execute(self, context):
        obj = context.active_object
        bm = bmesh.from_edit_mesh(obj.data)
        picked = [e.index for e in bm.select_history if isinstance(e, bmesh.types.BMVert)]
        selected = [v.index for v in bm.verts if v.select]
        if len(selected) != 2 or len(picked) < 2 or set(picked[-2:]) != set(selected):
            self.report({"ERROR"}, "select two vertices one after the other: the tip, then "
                                   "where the region ends")
            return {"CANCELLED"}
        first, last = picked[-2], picked[-1]
        bpy.ops.object.mode_set(mode="OBJECT")
        try:
            bridge.dualform().load_library(_library(context) or None)
            vertices, diagnosis = bridge.water_fill(obj, first, last)
            group = obj.vertex_groups.get(bridge.ROI_GROUP)
            if group is not None:
                obj.vertex_groups.remove(group)
            group = obj.vertex_groups.new(name=bridge.ROI_GROUP)
            group.add(vertices.tolist(), 1.0, "REPLACE")
            obj["dualform_roi_count"] = len(vertices)
            obj["dualform_roi_loops"] = diagnosis.loops
            obj["dualform_roi_suspect"] = diagnosis.suspect
            text = bridge.diagnosis_text(len(vertices), diagnosis)
        except Exception as error:  # the library's message, shown to the user
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        finally:
            bpy.ops.object.mode_set(mode="EDIT")
        self.report({"WARNING"} if diagnosis.suspect else {"INFO"}, text)
        return {"FINISHED"}


class DUALFORM_OT_add_handle(bpy.types.Operator):
    """Turn the selected vertices into a new handle group ('Dualform Handle N')"""

    bl_idname = "dualform.add_handle"
    bl_label = "Add Handle"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _edit_mesh_object(context) is not None

    def execute(self, context):
        obj = context.active_object
        bm = bmesh.from_edit_mesh(obj.data)
        selected = [v.index for v in bm.verts if v.select]
        if not selected:
            self.report({"ERROR"}, "select the handle's vertices first")
            return {"CANCELLED"}
        bpy.ops.object.mode_set(mode="OBJECT")
        name = f"{bridge.HANDLE_PREFIX} {len(bridge.handle_group_names(obj)) + 1}"
        group = obj.vertex_groups.new(name=name)
        group.add(selected, 1.0, "REPLACE")
        obj.vertex_groups.active_index = group.index
        bpy.ops.object.mode_set(mode="EDIT")
        self.report({"INFO"}, f"{name}: {len(selected)} vertices")
        return {"FINISHED"}


def _active_handle(obj) -> str:
    group = obj.vertex_groups.active
    if group is not None and group.name.startswith(bridge.HANDLE_PREFIX):
        return group.name
    return ""


class ViewMapping:
    """Mouse pixels to a motion in the object's space, in the view plane
    through the handle's pivot, as G and R do."""

    def __init__(self, context, obj, pivot_local) -> None:
        from bpy_extras import view3d_utils

        self._utils = view3d_utils
        self._region = context.region
        self._rv3d = context.region_data
        self._world = obj.matrix_world.copy()
        self._to_local = self._world.inverted()
        self._pivot_world = self._world @ Vector(pivot_local)
        self.pivot_pixel = view3d_utils.location_3d_to_region_2d(self._region, self._rv3d,
                                                                 self._pivot_world)

    def translation(self, start, now) -> np.ndarray:
        a = self._utils.region_2d_to_location_3d(self._region, self._rv3d, start, self._pivot_world)
        b = self._utils.region_2d_to_location_3d(self._region, self._rv3d, now, self._pivot_world)
        return np.array(self._to_local.to_3x3() @ (b - a), dtype=np.float64)

    def view_axis(self) -> np.ndarray:
        forward = self._rv3d.view_rotation @ Vector((0.0, 0.0, -1.0))
        return np.array(self._to_local.to_3x3() @ forward, dtype=np.float64)

    def angle(self, start, now) -> float:
        c = self.pivot_pixel
        a = math.atan2(start[1] - c[1], start[0] - c[0])
        b = math.atan2(now[1] - c[1], now[0] - c[0])
        return -math.degrees(b - a)


class DUALFORM_OT_drag(bpy.types.Operator):
    """Move (G) or rotate (R) the active handle group with the mouse; the
    mesh follows live. Enter or click keeps the result, Escape restores"""

    bl_idname = "dualform.drag"
    bl_label = "Dualform Drag"
    bl_options = {"REGISTER", "UNDO", "BLOCKING"}

    keep: EnumProperty(name="Keep", items=KEEP_ITEMS, default="MESH")

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and context.mode in {"OBJECT", "EDIT_MESH"}

    def invoke(self, context, event):
        if context.area is None or context.area.type != "VIEW_3D":
            self.report({"ERROR"}, "Dualform Drag runs in a 3D view")
            return {"CANCELLED"}
        obj = context.active_object
        if not self.start(context, obj):
            return {"CANCELLED"}
        self.mapping = ViewMapping(context, obj, self.drag.pivot)
        self.mouse_start = (event.mouse_region_x, event.mouse_region_y)
        self.timer = context.window_manager.event_timer_add(1.0 / 60.0, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    # The steps below take no window state beyond `mapping`, so a script
    # (tests/blender_checks.py) can drive them with its own events.
    def start(self, context, obj) -> bool:
        self.return_to_edit = context.mode == "EDIT_MESH"
        if self.return_to_edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            self.drag = bridge.DragEdit(obj, _active_handle(obj) or None, _library(context) or None)
        except Exception as error:
            self.report({"ERROR"}, str(error))
            self._restore_mode()
            return False
        self.rotating = False
        self.finishing = False
        self.timer = None
        return True

    def _restore_mode(self) -> None:
        if self.return_to_edit:
            bpy.ops.object.mode_set(mode="EDIT")

    def _motion(self, mouse) -> np.ndarray:
        if self.rotating:
            return bridge.motion_matrix(axis=self.mapping.view_axis(),
                                        degrees=self.mapping.angle(self.mouse_start, mouse),
                                        pivot=self.drag.pivot)
        return bridge.motion_matrix(translate=self.mapping.translation(self.mouse_start, mouse))

    def _header(self, context, text) -> None:
        if context.area is not None:
            context.area.header_text_set(text)

    def _end(self, context, keep: bool) -> set:
        if self.timer is not None:
            context.window_manager.event_timer_remove(self.timer)
        if keep:
            self.drag.finish(self.keep)
        else:
            self.drag.cancel()
        self._header(context, None)
        self._restore_mode()
        return {"FINISHED"} if keep else {"CANCELLED"}

    def modal(self, context, event):
        if event.type == "TIMER":
            if self.drag.apply_latest() and context.area is not None:
                context.area.tag_redraw()
            info = self.drag.last_info
            if info is not None:
                self._header(context, f"Dualform: generation {info.generation}, "
                                      f"{info.iterations} iterations"
                                      + (" (preview)" if info.partial else ""))
            if self.finishing and self.drag.settled:
                return self._end(context, keep=True)
            return {"RUNNING_MODAL"}
        if self.finishing:
            return {"RUNNING_MODAL"}
        try:
            if event.type == "MOUSEMOVE":
                self.drag.move(self._motion((event.mouse_region_x, event.mouse_region_y)))
            elif event.type in {"G", "R"} and event.value == "PRESS":
                self.rotating = event.type == "R"
                self.drag.move(self._motion((event.mouse_region_x, event.mouse_region_y)))
        except Exception as error:  # a failed set-up refuses every submit
            self.report({"ERROR"}, str(error))
            return self._end(context, keep=False)
        if event.type in {"RET", "NUMPAD_ENTER", "LEFTMOUSE"} and event.value == "PRESS":
            # Kept once the last motion's finished frame is in the mesh: the
            # timer keeps polling, the UI never waits on the solve.
            self.finishing = True
        elif event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            return self._end(context, keep=False)
        return {"RUNNING_MODAL"}

    def cancel(self, context):
        self._end(context, keep=False)


class DUALFORM_OT_deform(bpy.types.Operator):
    """Deform the mesh by moving the active handle group, without the mouse:
    the scripted twin of Dualform Drag (same session, solve and result)"""

    bl_idname = "dualform.deform"
    bl_label = "Dualform Deform"
    bl_options = {"REGISTER", "UNDO"}

    translate: FloatVectorProperty(name="Translate", size=3, default=(0.0, 0.0, 0.0),
                                   description="in the object's space")
    rotate_axis: FloatVectorProperty(name="Axis", size=3, default=(0.0, 0.0, 1.0))
    rotate_degrees: FloatProperty(name="Degrees", default=0.0)
    handle: StringProperty(name="Handle", default="",
                           description="handle group to move (empty: the active or last one)")
    keep: EnumProperty(name="Keep", items=KEEP_ITEMS, default="MESH")

    @classmethod
    def poll(cls, context):
        return DUALFORM_OT_drag.poll(context)

    def execute(self, context):
        obj = context.active_object
        in_edit = context.mode == "EDIT_MESH"
        if in_edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            drag = bridge.DragEdit(obj, self.handle or _active_handle(obj) or None,
                                   _library(context) or None)
            # Double precision, as Blender's mathutils would round to float.
            drag.move(bridge.motion_matrix(
                translate=np.array(self.translate, dtype=np.float64),
                axis=np.array(self.rotate_axis, dtype=np.float64),
                degrees=self.rotate_degrees, pivot=drag.pivot))
            drag.wait_and_apply()
            drag.finish(self.keep)
        except Exception as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        finally:
            if in_edit:
                bpy.ops.object.mode_set(mode="EDIT")
        return {"FINISHED"}


CLASSES = (DUALFORM_OT_water_fill_roi, DUALFORM_OT_add_handle, DUALFORM_OT_drag,
           DUALFORM_OT_deform)
