"""Runs inside Blender with a window (under Xvfb: Blender's undo needs
one), in the folder that holds dualform_blender.zip: the path a technical
artist walks on a real asset, with every operator's undo. Writes
OUT/artist_path.json and .npy files for tests/blender/test_artist_path.py.

xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup
    --python-exit-code 1 --python artist_path_checks.py -- PLY OUT HOOF_FILE T1X T1Y T1Z T2X T2Y T2Z

1. The add-on installed by docs/blender.md's commands.
2. The asset: the cow from PLY, UV-unwrapped by Blender's Smart UV Project,
   exported to glTF and imported again, so split at its UV seams.
3. Water-Fill from a copy of the hoof (771) and one of the knee (681); Add
   Handle on one copy of each hoof vertex.
4. Deform into the shape key "Step", then into "Lift"; one undo.
5. Exported to glTF with its shape keys, imported again.
Every operator is run as the UI runs it (it records its own undo step),
and undone: what comes back must be bit for bit what was there.
"""

import json
import os
import sys
from pathlib import Path

import bmesh
import bpy
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_arrays import key_positions, mesh_positions, shown  # noqa: E402
from documented_install import install_as_documented  # noqa: E402

np = numpy
# Debian 12's numpy 1.24 dropped numpy.bool, which Blender 3.4's glTF
# importer still uses: a packaging mismatch (docs/blender.md), patched here.
numpy.bool = bool

ply_path, out_dir, hoof_file, *moves = sys.argv[sys.argv.index("--") + 1:]
out = Path(out_dir)
first_move = tuple(float(t) for t in moves[:3])
second_move = tuple(float(t) for t in moves[3:])
hoof = [int(v) for v in Path(hoof_file).read_text().split()]
results = {"undo": {}}

install_as_documented()
import dualform_blender  # noqa: E402
from dualform_blender import bridge  # noqa: E402

results["addon"] = dualform_blender.__file__


def clear_scene():
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)


# -- 2. the asset
clear_scene()
bpy.ops.import_mesh.ply(filepath=ply_path)
source = bpy.context.selected_objects[0]
ply_rest = mesh_positions(source.data)
bpy.context.view_layer.objects.active = source
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.select_all(action="SELECT")
bpy.ops.uv.smart_project(angle_limit=1.15, island_margin=0.01)
bpy.ops.object.mode_set(mode="OBJECT")
for polygon in source.data.polygons:
    polygon.use_smooth = True
asset = str(out / "cow-seams.glb")
bpy.ops.export_scene.gltf(filepath=asset, export_format="GLB", use_selection=True)
clear_scene()
bpy.ops.import_scene.gltf(filepath=asset)
cow = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = cow
NAME = cow.name
rest = mesh_positions(cow.data)
results["asset"] = {"vertices": len(rest), "positions": len(np.unique(rest, axis=0))}


def copies(ply_vertex: int) -> np.ndarray:
    """The asset's vertices at the PLY vertex's position (the exporter and
    importer turn the axes exactly)."""
    return np.flatnonzero((rest == ply_rest[ply_vertex]).all(axis=1))


np.save(out / "rest.npy", rest)
np.save(out / "hoof_copies.npy", np.concatenate([copies(v) for v in hoof]))
bpy.ops.ed.undo_push(message="Import glTF")


def obj():
    # Undo reloads the data: the object is looked up again every time.
    return bpy.data.objects[NAME]


def state() -> dict:
    """Everything an operator may change, read from Edit Mode's mesh there."""
    o = obj()
    if bpy.context.mode == "EDIT_MESH":
        bm = bmesh.from_edit_mesh(o.data)
        co = np.array([v.co[:] for v in bm.verts], dtype=np.float32)
        layer = bm.verts.layers.deform.active
        groups = {g.name: [v.index for v in bm.verts if layer is not None and g.index in v[layer]]
                  for g in o.vertex_groups}
    else:
        co = mesh_positions(o.data)
        groups = {g.name: bridge.group_vertices(o, g.name).tolist() for g in o.vertex_groups}
    keys = []
    if o.data.shape_keys is not None and bpy.context.mode != "EDIT_MESH":
        keys = [(k.name, k.value, key_positions(o, k.name).tobytes())
                for k in o.data.shape_keys.key_blocks]
    return {"positions": co.tobytes(), "groups": groups, "keys": keys,
            "properties": {k: o[k] for k in o.keys() if k.startswith("dualform")}}


def run_with_undo(label: str, operator, **args):
    """Runs ``operator`` as the UI does, then Ctrl+Z (must bring back the
    state before exactly, in the mode it was run from), then Ctrl+Shift+Z
    (the result again, in Object Mode). Returns what the operator returned."""
    mode = bpy.context.mode
    before = state()
    returned = list(operator(**args))
    after = state()
    bpy.ops.ed.undo()
    undone = state()
    record = {"returned": returned, "changed": after != before, "undo_exact": undone == before,
              "undo_mode": bpy.context.mode == mode}
    bpy.ops.ed.redo()
    record["redo_exact"] = state() == after
    results["undo"][label] = record
    return returned


def select(vertices) -> None:
    """Selects ``vertices`` one after the other in Edit Mode, as clicks do."""
    if bpy.context.mode != "EDIT_MESH":
        bpy.ops.object.mode_set(mode="EDIT")
    bm = bmesh.from_edit_mesh(obj().data)
    bm.verts.ensure_lookup_table()
    for v in bm.verts:
        v.select = False
    bm.select_history.clear()
    for i in vertices:
        bm.verts[int(i)].select = True
        bm.select_history.add(bm.verts[int(i)])
    bmesh.update_edit_mesh(obj().data)
    bpy.ops.ed.undo_push(message="Select")


# -- 3. the ROI and the handle
select([copies(771)[0], copies(681)[-1]])
results["water_fill"] = run_with_undo("water_fill", bpy.ops.dualform.water_fill_roi)
results["roi"] = {k: obj()[f"dualform_roi_{k}"] for k in ("count", "loops", "suspect")}
np.save(out / "roi.npy", bridge.group_vertices(obj(), bridge.ROI_GROUP))

select([copies(v)[0] for v in hoof])
results["add_handle"] = run_with_undo("add_handle", bpy.ops.dualform.add_handle)
np.save(out / "handle.npy", bridge.group_vertices(obj(), "Dualform Handle 1"))

bpy.ops.object.mode_set(mode="OBJECT")
bpy.ops.ed.undo_push(message="Toggle Object Mode")
roi_before = bridge.group_vertices(obj(), bridge.ROI_GROUP)
run_with_undo("grow", bpy.ops.dualform.grow_roi, rings=2)
results["grown"] = obj()["dualform_roi_count"]
run_with_undo("shrink", bpy.ops.dualform.grow_roi, rings=-2)
results["grown_then_shrunk"] = obj()["dualform_roi_count"]
leg = obj().vertex_groups.new(name="Leg")
leg.add(roi_before.tolist(), 1.0, "REPLACE")
obj().vertex_groups.active_index = leg.index
bpy.ops.ed.undo_push(message="Leg group")
run_with_undo("group_as_roi", bpy.ops.dualform.group_as_roi)
results["group_as_roi"] = obj()["dualform_roi_count"]
run_with_undo("group_as_handle", bpy.ops.dualform.group_as_handle)
# Back to the state before the ROI edits: the Water-Filled leg and one handle.
for _ in range(5):
    bpy.ops.ed.undo()
results["back_to_the_leg"] = {
    "roi": bridge.group_vertices(obj(), bridge.ROI_GROUP).tolist() == roi_before.tolist(),
    "handles": bridge.handle_group_names(obj()),
    "leg_group": obj().vertex_groups.get("Leg") is not None,
}
obj().vertex_groups.active_index = obj().vertex_groups["Dualform Handle 1"].index
bpy.ops.ed.undo_push(message="Active group")

# -- 4. two edits into two named keys, then one undo
run_with_undo("deform", bpy.ops.dualform.deform, translate=first_move, keep="SHAPE_KEY",
              key_name="Step")
after_step = state()
np.save(out / "step_key.npy", key_positions(obj(), "Step"))
results["deform_lift"] = list(bpy.ops.dualform.deform(translate=second_move, keep="SHAPE_KEY",
                                                      key_name="Lift"))
results["keys_after_lift"] = {k.name: k.value for k in obj().data.shape_keys.key_blocks}
np.save(out / "lift_key.npy", key_positions(obj(), "Lift"))
np.save(out / "lift_shown.npy", shown(obj()))
bpy.ops.ed.undo()
undone = state()
results["one_undo"] = {
    "exact": undone == after_step,
    "keys": {k.name: k.value for k in obj().data.shape_keys.key_blocks},
}

# -- 5. to glTF with the shape keys, and back
pairs = {}
basis, step = key_positions(obj(), "Basis"), key_positions(obj(), "Step")
for b, s in zip(basis, step):
    pairs[b.tobytes()] = s
edited = str(out / "cow-step.glb")
bpy.ops.object.select_all(action="DESELECT")
obj().select_set(True)
bpy.ops.export_scene.gltf(filepath=edited, export_format="GLB", use_selection=True,
                          export_morph=True)
clear_scene()
bpy.ops.import_scene.gltf(filepath=edited)
back = bpy.context.selected_objects[0]
results["reimported_keys"] = {k.name: k.value for k in back.data.shape_keys.key_blocks}
back_basis, back_step = key_positions(back, "Basis"), key_positions(back, "Step")
found = [b.tobytes() in pairs for b in back_basis]
results["reimported_basis_found"] = all(found)
np.save(out / "reimported_basis.npy", back_basis)
np.save(out / "reimported_step.npy", back_step)
np.save(out / "reimported_expected.npy",
        np.array([pairs.get(b.tobytes(), b) for b in back_basis]))

(out / "artist_path.json").write_text(json.dumps(results, indent=1))
print("artist_path_checks: done")
bpy.ops.wm.quit_blender()
