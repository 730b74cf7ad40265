"""Runs inside headless Blender (tests/blender/test_blender_addon.py starts
it, in the folder that holds dualform_blender.zip): installs and enables
the add-on as docs/blender.md says, imports the cow from PLY, runs the
operators as a user would and saves what they produced in OUT for the test
to compare with the dualform tool.

blender -b --factory-startup --python-exit-code 1 --python blender_checks.py --
    PLY OUT HOOF_FILE TX TY TZ TX2 TY2 TZ2
"""

import json
import os
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_arrays import key_positions, positions, shown  # noqa: E402
from blender_steps import drag_stand_in, event, run_timer_until, select_in_order  # noqa: E402
from documented_install import install_as_documented  # noqa: E402

ply_path, out_dir, hoof_file, *moves = sys.argv[sys.argv.index("--") + 1:]
out = Path(out_dir)
translate = tuple(float(t) for t in moves[:3])
second_translate = tuple(float(t) for t in moves[3:])
hoof = [int(v) for v in Path(hoof_file).read_text().split()]
results = {}


def duplicate(obj, name):
    copy = obj.copy()
    copy.data = obj.data.copy()
    copy.name = name
    bpy.context.collection.objects.link(copy)
    return copy


# -- install and enable
install_as_documented()
import dualform  # noqa: E402  (importable once the add-on is enabled)
from dualform_blender import bridge  # noqa: E402

results["enabled"] = "dualform_blender" in bpy.context.preferences.addons
results["package"] = dualform.__file__
results["library"] = dualform.load_library()._name

# -- the cow from PLY
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
bpy.ops.import_mesh.ply(filepath=ply_path)
cow = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = cow
np.save(out / "rest.npy", positions(cow))

# -- Water-Fill ROI from two vertices selected in order, then a handle
select_in_order(cow, [771, 681])
results["water_fill"] = list(bpy.ops.dualform.water_fill_roi())
results["diagnosis"] = {k: cow[f"dualform_roi_{k}"] for k in ("count", "loops", "suspect")}
select_in_order(cow, [771, 681, 5])
try:
    bpy.ops.dualform.water_fill_roi()
    results["three_selected"] = "accepted"
except RuntimeError as error:  # an operator's ERROR report
    results["three_selected"] = str(error)
select_in_order(cow, hoof)
results["add_handle"] = list(bpy.ops.dualform.add_handle())
bpy.ops.object.mode_set(mode="OBJECT")
np.save(out / "roi.npy", bridge.group_vertices(cow, bridge.ROI_GROUP))
np.save(out / "handle.npy", bridge.group_vertices(cow, "Dualform Handle 1"))

as_key = duplicate(cow, "cow key")
dragged = duplicate(cow, "cow dragged")
escaped = duplicate(cow, "cow escaped")

# -- the scripted twin, result kept in the mesh
bpy.context.view_layer.objects.active = cow
results["deform"] = list(bpy.ops.dualform.deform(translate=translate, keep="MESH"))
np.save(out / "deformed.npy", positions(cow))

# -- the same as a shape key: the basis stays, the key at 1 gives the result
bpy.context.view_layer.objects.active = as_key
results["deform_key"] = list(bpy.ops.dualform.deform(translate=translate, keep="SHAPE_KEY"))
np.save(out / "key_basis.npy", positions(as_key))
np.save(out / "key_evaluated.npy", shown(as_key))
results["shape_keys"] = [k.name for k in as_key.data.shape_keys.key_blocks]

# -- a second edit, into a named key: it starts from the shape shown, and
# the first key goes to 0, so the two never add up
np.save(out / "mix_before_lift.npy", shown(as_key))
results["deform_lift"] = list(bpy.ops.dualform.deform(translate=second_translate,
                                                      keep="SHAPE_KEY", key_name="Lift"))
results["lift_keys"] = {k.name: k.value for k in as_key.data.shape_keys.key_blocks}
np.save(out / "lift_key.npy", key_positions(as_key, "Lift"))
np.save(out / "lift_evaluated.npy", shown(as_key))
np.save(out / "first_key.npy", key_positions(as_key, bridge.SHAPE_KEY_NAME))
try:
    bpy.ops.dualform.deform(translate=translate, keep="MESH")
    results["mesh_with_keys"] = "accepted"
except RuntimeError as error:
    results["mesh_with_keys"] = str(error)


# -- the modal operator, driven by synthetic events (blender_steps.py)
# 1024 pixels a unit: the test's translation lands on whole pixels.
mouse_end = (round(translate[0] * 1024), round(translate[1] * 1024))
driver = drag_stand_in(dragged)
for step in range(1, 11):
    driver.modal(bpy.context, event("MOUSEMOVE", mouse_end[0] * step // 10,
                                    mouse_end[1] * step // 10))
    driver.modal(bpy.context, event("TIMER"))
driver.modal(bpy.context, event("RET", *mouse_end, value="PRESS"))
results["modal_enter"] = list(run_timer_until(driver, lambda s: s != {"RUNNING_MODAL"}))
np.save(out / "modal.npy", positions(dragged))

rest_bytes = positions(escaped).tobytes()
driver = drag_stand_in(escaped)
driver.modal(bpy.context, event("MOUSEMOVE", *mouse_end))
run_timer_until(driver, lambda s: driver.drag.applied > 0)
results["escape_moved_first"] = positions(escaped).tobytes() != rest_bytes
results["modal_escape"] = list(driver.modal(bpy.context, event("ESC", value="PRESS")))
results["escape_restored_bitwise"] = positions(escaped).tobytes() == rest_bytes

# -- a Water-Fill that leaks: the tail tip cut through the rump
select_in_order(cow, [2334, 1959])
results["suspect_fill"] = list(bpy.ops.dualform.water_fill_roi())
results["suspect_diagnosis"] = {k: cow[f"dualform_roi_{k}"] for k in ("count", "loops", "suspect")}
bpy.ops.object.mode_set(mode="OBJECT")

(out / "results.json").write_text(json.dumps(results, indent=1))
print("blender_checks: done")
