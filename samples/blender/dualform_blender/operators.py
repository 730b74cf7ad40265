"""The add-on's operators: the ROI (Water-Fill, grow or shrink, a vertex
group as ROI), handle groups (from the selection or a vertex group), the
modal Dualform Drag and its typed twin Dualform Deform. Each that changes
something records one undo step (ObjectModeStep says how)."""

import math

import bmesh
import bpy
import numpy as np
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, StringProperty)
from mathutils import Vector

from . import bridge

KEEP_ITEMS = [
    ("MESH", "Mesh", "write the result into the mesh (a mesh without shape keys)"),
    ("SHAPE_KEY", "Shape Key", "add the result as a new shape key at value 1, made from the "
                               "shape shown; the other keys go to 0, so edits never add up"),
    ("CORRECTIVE", "Corrective", "for a mesh an Armature modifier poses: bake the edit into a "
                                 "new shape key holding only the edit, in rest space, which the "
                                 "armature plays at this pose; the other keys keep their values"),
]
DRIVER_DESCRIPTION = ("Corrective: drive the key by the angle of the bone nearest the ROI (0 at "
                      "rest, 1 at this pose)")


def _library(context) -> str:
    addon = context.preferences.addons.get(__package__)
    return addon.preferences.library_path if addon else ""


def _load_library(context) -> None:
    bridge.dualform().load_library(_library(context) or None)


def _mesh_object(context):
    obj = context.active_object
    return obj if obj is not None and obj.type == "MESH" else None


def _edit_mesh_object(context):
    obj = _mesh_object(context)
    return obj if obj is not None and context.mode == "EDIT_MESH" else None


def _has_active_group(context) -> bool:
    obj = _mesh_object(context)
    return obj is not None and obj.vertex_groups.active is not None


def push_undo(label: str) -> None:
    if bpy.ops.ed.undo_push.poll():
        bpy.ops.ed.undo_push(message=label)


class ObjectModeStep:
    """The operator's work in object mode (where vertex groups, shape keys
    and the mesh's arrays are current), back to edit mode after it when it
    was called there. Once ``finished`` is set, the step records one undo
    step, in object mode: Blender's edit-mode undo would restore the mesh's
    vertices and weights but not a new vertex group's name, a shape key or
    the object's properties, so the step is the whole-file kind, and undo
    brings back exactly what was there (in edit mode, with the selection,
    when the operator ran there). The operators have no UNDO option, which
    would record a second, edit-mode step."""

    def __init__(self, context, label: str) -> None:
        self.edit = context.mode == "EDIT_MESH"
        self.label = label
        self.finished = False

    def __enter__(self):
        if self.edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        return self

    def __exit__(self, *exc) -> None:
        if self.finished:
            push_undo(self.label)
        if self.edit:
            bpy.ops.object.mode_set(mode="EDIT")


def _store_roi(obj, vertices: np.ndarray, count: int, diagnosis=None) -> None:
    """The ROI group, and what the panel shows of it (cut loops only for a
    Water-Filling)."""
    bridge.set_group(obj, bridge.ROI_GROUP, vertices)
    obj["dualform_roi_count"] = count
    for key in ("dualform_roi_loops", "dualform_roi_suspect"):
        if key in obj:
            del obj[key]
    if diagnosis is not None:
        obj["dualform_roi_loops"] = diagnosis.loops
        obj["dualform_roi_suspect"] = diagnosis.suspect


class DUALFORM_OT_water_fill_roi(bpy.types.Operator):
    """Water-Fill from the two selected vertices: first the limb's tip, then
    where the region ends; the region becomes the 'Dualform ROI' group"""

    bl_idname = "dualform.water_fill_roi"
    bl_label = "Water-Fill ROI"
    bl_options = {"REGISTER"}

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
        with ObjectModeStep(context, self.bl_label) as step:
            try:
                _load_library(context)
                vertices, count, diagnosis = bridge.water_fill(obj, first, last)
            except Exception as error:  # the library's message, shown to the user
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            _store_roi(obj, vertices, count, diagnosis)
            step.finished = True
        text = bridge.diagnosis_text(count, len(vertices), diagnosis)
        self.report({"WARNING"} if diagnosis.suspect else {"INFO"}, text)
        return {"FINISHED"}


class DUALFORM_OT_grow_roi(bpy.types.Operator):
    """Grow (or, with negative rings, shrink) the 'Dualform ROI' group by
    whole edge rings of the surface"""

    bl_idname = "dualform.grow_roi"
    bl_label = "Grow ROI"
    bl_options = {"REGISTER"}

    rings: IntProperty(name="Rings", default=1, min=-100, max=100,
                       description="edge rings to add (negative: to remove)")

    @classmethod
    def poll(cls, context):
        obj = _mesh_object(context)
        return obj is not None and obj.vertex_groups.get(bridge.ROI_GROUP) is not None

    def execute(self, context):
        obj = context.active_object
        with ObjectModeStep(context, self.bl_label) as step:
            roi = bridge.group_vertices(obj, bridge.ROI_GROUP)
            try:
                _load_library(context)
                vertices, count = bridge.grow(obj, roi, self.rings)
            except Exception as error:
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            if vertices.size == 0:
                self.report({"ERROR"}, f"shrinking by {-self.rings} ring(s) leaves no ROI")
                return {"CANCELLED"}
            _store_roi(obj, vertices, count)
            step.finished = True
        self.report({"INFO"}, f"Dualform ROI: {count} vertices")
        return {"FINISHED"}


class DUALFORM_OT_group_as_roi(bpy.types.Operator):
    """Use the active vertex group (with every seam copy of its vertices) as
    the 'Dualform ROI'"""

    bl_idname = "dualform.group_as_roi"
    bl_label = "Active Group as ROI"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        return _has_active_group(context)

    def execute(self, context):
        obj = context.active_object
        source = obj.vertex_groups.active.name
        with ObjectModeStep(context, self.bl_label) as step:
            chosen = bridge.group_vertices(obj, source)
            if chosen.size == 0:
                self.report({"ERROR"}, f"the vertex group '{source}' is empty")
                return {"CANCELLED"}
            try:
                _load_library(context)
                vertices, count = bridge.with_copies(obj, chosen)
            except Exception as error:
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            _store_roi(obj, vertices, count)
            step.finished = True
        self.report({"INFO"}, f"Dualform ROI from '{source}': {count} vertices")
        return {"FINISHED"}


def _add_handle(operator, context, step: ObjectModeStep, chosen: np.ndarray, source: str):
    obj = context.active_object
    if chosen.size == 0:
        operator.report({"ERROR"}, f"{source} has no vertices")
        return {"CANCELLED"}
    try:
        _load_library(context)
        vertices, count = bridge.with_copies(obj, chosen)
    except Exception as error:
        operator.report({"ERROR"}, str(error))
        return {"CANCELLED"}
    name = bridge.next_handle_name(obj)
    group = bridge.set_group(obj, name, vertices)
    obj.vertex_groups.active_index = group.index
    operator.report({"INFO"}, f"{name}: {count} vertices")
    step.finished = True
    return {"FINISHED"}


class DUALFORM_OT_add_handle(bpy.types.Operator):
    """Turn the selected vertices into a new handle group ('Dualform Handle N')"""

    bl_idname = "dualform.add_handle"
    bl_label = "Add Handle"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        return _edit_mesh_object(context) is not None

    def execute(self, context):
        with ObjectModeStep(context, self.bl_label) as step:
            mesh = context.active_object.data
            selected = np.zeros(len(mesh.vertices), dtype=bool)
            mesh.vertices.foreach_get("select", selected)
            return _add_handle(self, context, step, np.flatnonzero(selected), "the selection")


class DUALFORM_OT_group_as_handle(bpy.types.Operator):
    """Turn the active vertex group into a new handle group ('Dualform Handle N')"""

    bl_idname = "dualform.group_as_handle"
    bl_label = "Active Group as Handle"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        return _has_active_group(context)

    def execute(self, context):
        obj = context.active_object
        source = obj.vertex_groups.active.name
        with ObjectModeStep(context, self.bl_label) as step:
            return _add_handle(self, context, step, bridge.group_vertices(obj, source),
                               f"the vertex group '{source}'")


def _active_handle(obj) -> str:
    group = obj.vertex_groups.active
    if group is not None and group.name.startswith(bridge.HANDLE_PREFIX):
        return group.name
    return ""


def _corrective_text(drag) -> str:
    """What a bake in a pose found: the vertices corrected, damped ones."""
    info = drag.corrective
    if info is None:
        return ""
    text = f"; {info.corrective_vertex_count} vertices corrected in rest space"
    if info.corrective_damped_count:
        text += (f", {info.corrective_damped_count} of them damped (their skinning is nearly "
                 f"singular: condition number up to {info.corrective_worst_condition:.3g})")
    return text


def _kept_text(drag) -> str:
    target = drag.target
    if isinstance(target, bridge.ShapeKeyTarget) and target.additive:
        text = (f"Dualform: kept as the corrective shape key '{target.key.name}' at value 1"
                + _corrective_text(drag))
        if drag.driven_by:
            bone, degrees = drag.driven_by
            text += (f"; driven by the angle of the bone '{bone}' (0 at rest, 1 at this "
                     f"pose's {degrees} degrees)")
        elif drag.driver and drag.corrective is not None:
            text += "; no driver: every bone near the ROI stands at rest"
        return text
    if isinstance(target, bridge.ShapeKeyTarget):
        text = f"Dualform: kept as the shape key '{target.key.name}' at value 1"
        zeroed = target.zeroed()
        if zeroed:
            text += f"; set to 0: {', '.join(zeroed)} (each key holds a whole shape)"
        return text + _corrective_text(drag)
    return "Dualform: kept in the mesh" + _corrective_text(drag)


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
    bl_options = {"REGISTER", "BLOCKING"}

    keep: EnumProperty(name="Keep", items=KEEP_ITEMS, default="MESH")
    key_name: StringProperty(name="Shape Key", default=bridge.SHAPE_KEY_NAME,
                             description="the new shape key's name (keep: Shape Key or "
                                         "Corrective)")
    driver: BoolProperty(name="Drive by the Pose", default=True, description=DRIVER_DESCRIPTION)

    @classmethod
    def poll(cls, context):
        return _mesh_object(context) is not None and context.mode in {"OBJECT", "EDIT_MESH"}

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
            self.drag = bridge.DragEdit(obj, _active_handle(obj) or None,
                                        _library(context) or None, self.keep, self.key_name,
                                        self.driver)
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
            try:
                self.drag.finish()
            except Exception as error:  # a bake the library refused
                self.report({"ERROR"}, str(error))
                self.drag.target.undo()
                self._header(context, None)
                self._restore_mode()
                return {"CANCELLED"}
            self.report({"INFO"}, _kept_text(self.drag))
            push_undo(self.bl_label)
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
    """Deform the mesh by moving the active handle group by the numbers
    typed: the twin of Dualform Drag (same session, solve and result)"""

    bl_idname = "dualform.deform"
    bl_label = "Dualform Deform"
    bl_options = {"REGISTER"}

    translate: FloatVectorProperty(name="Offset", size=3, default=(0.0, 0.0, 0.0),
                                   subtype="TRANSLATION", description="in the object's space")
    rotate_axis: FloatVectorProperty(name="Axis", size=3, default=(0.0, 0.0, 1.0))
    rotate_degrees: FloatProperty(name="Degrees", default=0.0,
                                  description="about the handle group's centroid, before the "
                                              "offset")
    handle: StringProperty(name="Handle", default="",
                           description="handle group to move (empty: the active or last one)")
    keep: EnumProperty(name="Keep", items=KEEP_ITEMS, default="MESH")
    key_name: StringProperty(name="Shape Key", default=bridge.SHAPE_KEY_NAME,
                             description="the new shape key's name (keep: Shape Key or "
                                         "Corrective)")
    driver: BoolProperty(name="Drive by the Pose", default=True, description=DRIVER_DESCRIPTION)

    @classmethod
    def poll(cls, context):
        return DUALFORM_OT_drag.poll(context)

    def execute(self, context):
        obj = context.active_object
        with ObjectModeStep(context, self.bl_label) as step:
            try:
                drag = bridge.DragEdit(obj, self.handle or _active_handle(obj) or None,
                                       _library(context) or None, self.keep, self.key_name,
                                       self.driver)
            except Exception as error:
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            try:
                # Double precision, as Blender's mathutils would round to float.
                drag.move(bridge.motion_matrix(
                    translate=np.array(self.translate, dtype=np.float64),
                    axis=np.array(self.rotate_axis, dtype=np.float64),
                    degrees=self.rotate_degrees, pivot=drag.pivot))
                drag.wait_and_apply()
            except Exception as error:
                drag.cancel()
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            try:
                drag.finish()
            except Exception as error:  # a bake the library refused
                drag.target.undo()
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            self.report({"INFO"}, _kept_text(drag))
            step.finished = True
        return {"FINISHED"}


CLASSES = (DUALFORM_OT_water_fill_roi, DUALFORM_OT_grow_roi, DUALFORM_OT_group_as_roi,
           DUALFORM_OT_add_handle, DUALFORM_OT_group_as_handle, DUALFORM_OT_drag,
           DUALFORM_OT_deform)
