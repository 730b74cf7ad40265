"""Dualform for Blender: Water-Fill a limb from two clicks, add handle
groups, drag them with the mesh following live; on a character an Armature
modifier poses, edit the pose shown and bake a corrective shape key
(docs/blender.md)."""

bl_info = {
    "name": "Dualform",
    "author": "Dualform",
    "version": (0, 2, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > Dualform",
    "description": "Real-time ROI mesh deformation (dual Laplacian) through libdualform",
    "category": "Mesh",
}

import os
import sys


def find_package() -> None:
    """Makes ``import dualform`` work: the folder in the add-on's
    preferences first, then the copy bundled in the add-on (vendor/), then
    whatever Blender's Python already finds (pip install)."""
    import bpy

    here = os.path.dirname(os.path.abspath(__file__))
    addon = bpy.context.preferences.addons.get(__name__)
    folders = []
    if addon is not None and addon.preferences.package_path:
        folders.append(bpy.path.abspath(addon.preferences.package_path))
    folders.append(os.path.join(here, "vendor"))
    for folder in reversed(folders):
        if os.path.isdir(os.path.join(folder, "dualform")) and folder not in sys.path:
            sys.path.insert(0, folder)


def register() -> None:
    import bpy

    from . import operators, panel

    for cls in panel.CLASSES + operators.CLASSES:
        bpy.utils.register_class(cls)
    panel.register_settings()
    find_package()


def unregister() -> None:
    import bpy

    from . import operators, panel

    panel.unregister_settings()
    for cls in reversed(panel.CLASSES + operators.CLASSES):
        bpy.utils.unregister_class(cls)
