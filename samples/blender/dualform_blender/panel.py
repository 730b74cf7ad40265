"""The sidebar panel (3D view, N, tab 'Dualform') and the preferences."""

import bpy
from bpy.props import StringProperty

from . import bridge


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


class VIEW3D_PT_dualform(bpy.types.Panel):
    bl_label = "Dualform"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Dualform"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        col = layout.column(align=True)
        col.label(text="1. Select the tip, then the end")
        col.operator("dualform.water_fill_roi", icon="MOD_FLUIDSIM")
        col.label(text="2. Select the handle's vertices")
        col.operator("dualform.add_handle", icon="EMPTY_ARROWS")
        col.separator()
        col.label(text="3. Drag: G move, R rotate")
        col.operator("dualform.drag", text="Drag into Mesh", icon="VIEW_PAN").keep = "MESH"
        col.operator("dualform.drag", text="Drag as Shape Key",
                     icon="SHAPEKEY_DATA").keep = "SHAPE_KEY"
        if obj is None or obj.type != "MESH":
            return
        box = layout.box()
        if "dualform_roi_count" in obj:
            box.label(text=f"ROI: {obj['dualform_roi_count']} vertices, "
                           f"{obj['dualform_roi_loops']} cut loop(s)")
            if obj["dualform_roi_suspect"]:
                box.label(text="Suspect: most likely leaked past the limb", icon="ERROR")
        else:
            box.label(text="ROI: none yet")
        handles = bridge.handle_group_names(obj)
        box.label(text=f"Handle groups: {len(handles)}")
        active = obj.vertex_groups.active
        if active is not None and active.name in handles:
            box.label(text=f"Moves: {active.name}")


CLASSES = (DualformPreferences, VIEW3D_PT_dualform)
