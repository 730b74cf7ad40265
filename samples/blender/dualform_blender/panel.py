"""The sidebar panel (3D view, N, tab 'Dualform'), the numbers it keeps
per scene, and the preferences."""

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, PointerProperty, StringProperty)

from . import bridge, skin
from .operators import DRIVER_DESCRIPTION, KEEP_ITEMS


class DualformPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    package_path: StringProperty(
        name="Python package folder", subtype="DIR_PATH",
        description="the folder holding the dualform package (e.g. sdk/python of a checkout); "
                    "empty: the copy bundled in the add-on, or an installed one")
    library_path: StringProperty(
        name="Library", subtype="FILE_PATH",
        description="libdualform.so to load; empty: the package's rule (DUALFORM_LIBRARY, the "
                    "bundled copy, the build tree, the system loader)")

    def draw(self, context):
        self.layout.prop(self, "package_path")
        self.layout.prop(self, "library_path")
        self.layout.label(text="Changes to the package folder take effect after a restart.")


class DualformSettings(bpy.types.PropertyGroup):
    """What the panel's buttons use: the typed motion, how to keep it, the
    ROI's growth step."""

    translate: FloatVectorProperty(name="Offset", size=3, subtype="TRANSLATION",
                                   description="the handle group's offset, in the object's space")
    rotate_axis: FloatVectorProperty(name="Axis", size=3, default=(0.0, 0.0, 1.0),
                                     subtype="XYZ")
    rotate_degrees: FloatProperty(name="Degrees", default=0.0,
                                  description="about the handle group's centroid, before the "
                                              "offset")
    keep: EnumProperty(name="Keep", items=KEEP_ITEMS, default="SHAPE_KEY")
    key_name: StringProperty(name="Shape Key", default=bridge.SHAPE_KEY_NAME,
                             description="the new shape key's name")
    driver: BoolProperty(name="Drive by the Pose", default=True, description=DRIVER_DESCRIPTION)
    rings: IntProperty(name="Rings", default=1, min=1, max=100,
                       description="edge rings to grow or shrink the ROI by")


class VIEW3D_PT_dualform(bpy.types.Panel):
    bl_label = "Dualform"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Dualform"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        settings = context.scene.dualform
        col = layout.column(align=True)
        col.label(text="1. Select the tip, then the end")
        col.operator("dualform.water_fill_roi", icon="MOD_FLUIDSIM")
        row = col.row(align=True)
        row.operator("dualform.grow_roi", text="Grow", icon="ADD").rings = settings.rings
        row.operator("dualform.grow_roi", text="Shrink", icon="REMOVE").rings = -settings.rings
        row.prop(settings, "rings", text="")
        col.operator("dualform.group_as_roi", icon="GROUP_VERTEX")
        col.separator()
        col.label(text="2. Select the handle's vertices")
        col.operator("dualform.add_handle", icon="EMPTY_ARROWS")
        col.operator("dualform.group_as_handle", icon="GROUP_VERTEX")
        col.separator()
        col.label(text="3. Move the active handle")
        col.row(align=True).prop(settings, "keep", expand=True)
        corrective = settings.keep == "CORRECTIVE"
        if settings.keep != "MESH":
            col.prop(settings, "key_name", text="Key")
        if corrective:
            col.prop(settings, "driver")
        col.prop(settings, "translate")
        col.prop(settings, "rotate_axis")
        col.prop(settings, "rotate_degrees")
        deform = col.operator("dualform.deform", text="Bake Corrective" if corrective else "Deform",
                              icon="CHECKMARK")
        deform.translate = settings.translate
        deform.rotate_axis = settings.rotate_axis
        deform.rotate_degrees = settings.rotate_degrees
        for operator in (deform, col.operator("dualform.drag", text="Drag (G move, R rotate)",
                                              icon="VIEW_PAN")):
            operator.keep = settings.keep
            operator.key_name = settings.key_name
            operator.driver = settings.driver
        if obj is None or obj.type != "MESH":
            return
        box = layout.box()
        try:
            modifier = skin.armature_modifier(obj)
        except ValueError as error:
            box.label(text="Cannot pose it exactly:", icon="ERROR")
            box.label(text=str(error))
        else:
            if modifier is not None:
                box.label(text=f"Posed: {modifier.object.name}, frame "
                               f"{context.scene.frame_current}", icon="ARMATURE_DATA")
        if "dualform_roi_count" in obj:
            text = f"ROI: {obj['dualform_roi_count']} vertices"
            if "dualform_roi_loops" in obj:
                text += f", {obj['dualform_roi_loops']} cut loop(s)"
            box.label(text=text)
            if obj.get("dualform_roi_suspect"):
                box.label(text="Suspect: most likely leaked past the limb", icon="ERROR")
        else:
            box.label(text="ROI: none yet")
        handles = bridge.handle_group_names(obj)
        box.label(text=f"Handle groups: {len(handles)}")
        active = obj.vertex_groups.active
        if active is not None and active.name in handles:
            box.label(text=f"Moves: {active.name}")


CLASSES = (DualformPreferences, DualformSettings, VIEW3D_PT_dualform)


def register_settings() -> None:
    bpy.types.Scene.dualform = PointerProperty(type=DualformSettings)


def unregister_settings() -> None:
    del bpy.types.Scene.dualform
