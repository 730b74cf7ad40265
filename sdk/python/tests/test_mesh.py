"""Meshes from numpy arrays and files, and their ROIs and picks."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import dualform as dfm
from conftest import tetrahedron


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_arrays_round_trip(context, dtype):
    positions, triangles = tetrahedron()
    with dfm.Mesh.from_arrays(context, positions.astype(dtype), triangles) as mesh:
        info = mesh.info
        assert (info.vertex_count, info.triangle_count) == (4, 4)
        assert np.array_equal(mesh.positions(), positions)
        assert mesh.positions(np.float32).dtype == np.float32
        assert np.array_equal(mesh.triangles(), triangles)
        assert mesh.summary.closed
        n = mesh.normals()
        assert np.allclose(np.linalg.norm(n, axis=1), 1.0)


def test_strided_rows_are_read_in_place(context):
    positions, triangles = tetrahedron()
    wide = np.zeros((4, 5))
    wide[:, 1:4] = positions
    with dfm.Mesh.from_arrays(context, wide[:, 1:4], triangles.astype(np.int64)) as mesh:
        assert np.array_equal(mesh.positions(), positions)


def test_positions_written_into_the_callers_array(cow):
    out = np.zeros((cow.vertex_count, 3), dtype=np.float32)
    assert cow.positions(out=out) is out
    assert np.array_equal(out, cow.positions().astype(np.float32))


def test_save_and_load(cow, context, tmp_path):
    for name in ("cow.ply", "cow.off", "cow.obj"):
        cow.save(tmp_path / name)
        with dfm.Mesh.load(context, tmp_path / name) as back:
            assert np.array_equal(back.triangles(), cow.triangles())
            tolerance = 0.0 if name == "cow.ply" else 1e-9
            assert np.abs(back.positions() - cow.positions()).max() <= tolerance
    cow.save(tmp_path / "float.ply", ply_float=True, ply_encoding=dfm.PlyEncoding.ASCII)
    with dfm.Mesh.load(context, tmp_path / "float.ply") as back:
        assert np.array_equal(back.positions(), cow.positions().astype(np.float32))


def test_water_fill_of_the_cow_leg(cow):
    with cow.water_fill(771, 681) as roi:
        assert len(roi) == 138
        assert roi.diagnosis == dfm.WaterFillDiagnosis(loops=1, bounded_by_last_loop=True,
                                                        suspect=False)
        vertices = roi.vertices()
        assert vertices.dtype == np.uint32 and np.all(np.diff(vertices.astype(np.int64)) > 0)
        with roi.boundary() as boundary, roi.grow(1) as grown, grown.difference(roi) as ring:
            assert 0 < len(boundary) < len(roi)
            assert len(grown) == len(roi) + len(ring)
            with ring.union(roi) as again:
                assert np.array_equal(again.vertices(), grown.vertices())


def test_two_clicks_give_the_water_fill(cow):
    rest = cow.positions()
    target = 0.5 * (rest[771] + rest[681])
    camera = dfm.Camera(eye=target + [0.5, -0.3, 0.0], target=target, up=(0, 1, 0),
                        fov_y_degrees=40.0, width=640, height=480)
    first, last = camera.project(rest[771]), camera.project(rest[681])
    assert cow.pick(camera, *first).vertex == 771
    assert cow.pick(camera, *last).vertex == 681
    assert cow.pick(camera, 1.0, 1.0) is None
    with cow.water_fill_clicks(camera, first, last) as clicked, cow.water_fill(771, 681) as filled:
        assert np.array_equal(clicked.vertices(), filled.vertices())
        assert clicked.diagnosis == filled.diagnosis


def test_ball_list_all_and_subdivide(cow):
    with cow.roi_ball(771, 0.03) as ball, cow.roi_all() as everything:
        assert 0 < len(ball) < 100
        assert len(everything) == cow.vertex_count
        with cow.roi_from_vertices([5, 3, 5, 9]) as listed:
            assert listed.vertices().tolist() == [3, 5, 9]
    with cow.subdivide(1) as fine:
        assert fine.vertex_count > cow.vertex_count


def test_seam_split_arrays_weld_and_keep_their_numbering(cow, context, tmp_path):
    # Every triangle of the cow gets its own three copies, as a renderer
    # with a UV seam on every edge would hold it: the weld joins them back
    # into the cow's 2,904 surface vertices, and reads come in the split
    # numbering, every copy with its surface vertex's position.
    positions = cow.positions()
    triangles = cow.triangles()
    split = positions[triangles.reshape(-1)]
    corners = np.arange(split.shape[0], dtype=np.uint32).reshape(-1, 3)
    with dfm.Mesh.from_arrays(context, split, corners, weld=0) as mesh:
        info = mesh.info
        assert info.vertex_count == split.shape[0]
        assert info.surface_vertex_count == cow.vertex_count
        assert np.array_equal(mesh.positions(), split)
        lowest = mesh.surface_map()
        assert np.array_equal(split[lowest], split)
        assert np.all(lowest <= np.arange(split.shape[0]))
        mesh.save(tmp_path / "split.glb")
        with dfm.Mesh.load(context, tmp_path / "split.glb") as back:
            assert back.info.surface_vertex_count == cow.vertex_count
            assert np.array_equal(back.positions(), split.astype(np.float32).astype(np.float64))
    with dfm.Mesh.from_arrays(context, split, corners) as apart:
        assert apart.info.surface_vertex_count == split.shape[0]


def test_info_is_read_once_and_again_after_the_rest_pose_changes(cow):
    first = cow.info
    assert cow.info is first and cow.vertex_count == first.vertex_count
    with cow.water_fill(771, 681) as roi, dfm.Session(cow, roi, [[771]]) as s:
        s.set_translation(0, [0.05, 0.0, 0.0])
        s.wait(s.submit())
        s.bake()
    assert cow.info.bake_count == 1 and cow.info != first
    cow.undo_bake()
    assert cow.info.bake_count == 0 and cow.info.redo_count == 1
    cow.set_positions(cow.positions() * 2.0)
    assert cow.info.diagonal == pytest.approx(2.0 * first.diagonal)
    cow.close()
    with pytest.raises(dfm.InvalidHandleError):
        cow.info


def test_a_triangle_that_repeats_a_vertex_is_dropped_with_a_warning(context):
    positions, triangles = tetrahedron()
    triangles = np.vstack([triangles, [[0, 1, 1]]])
    with dfm.Mesh.from_arrays(context, positions, triangles) as mesh:
        assert np.array_equal(mesh.triangles(), triangles[:4])
    assert context.log_messages[-1] == (dfm.LogLevel.WARNING, dfm.LogId.LOAD_WARNING,
                                        "dfm_mesh_create: triangle 4 repeats a vertex; dropped")


def test_a_saved_glb_names_its_mesh_after_the_file(cow, tmp_path):
    cow.save(tmp_path / "cow-leg.glb")
    data = (tmp_path / "cow-leg.glb").read_bytes()
    length = int.from_bytes(data[12:16], "little")
    document = json.loads(data[20:20 + length])
    assert document["meshes"][0]["name"] == "cow-leg"
    assert document["nodes"][0]["name"] == "cow-leg"


FBX = Path(__file__).resolve().parents[3] / "tests" / "data" / "fbx"


def test_an_fbx_edit_goes_back_into_its_file_or_as_a_blend_shape_channel(context, tmp_path):
    try:
        strip = dfm.Mesh.load(context, FBX / "strip.fbx")
    except dfm.UnsupportedError as e:
        pytest.skip(f"this build reads no FBX: {e}")
    with strip:
        assert strip.info.vertex_count == 21
        rest = strip.positions()
        lifted = rest.copy()
        lifted[rest[:, 0] > 1.0, 1] += 0.1
        strip.set_positions(lifted)
        strip.save(tmp_path / "edited.fbx")
        strip.save(tmp_path / "lift.fbx", morph_target="Lift")
    with dfm.Mesh.load(context, tmp_path / "edited.fbx") as edited:
        assert np.allclose(edited.positions(), lifted, rtol=0, atol=1e-12)
    with dfm.Mesh.load(context, tmp_path / "lift.fbx") as kept:
        assert np.array_equal(kept.positions(), rest)
        assert b"Lift\x00\x01Geometry" in (tmp_path / "lift.fbx").read_bytes()


def test_fbx_is_written_only_back_into_its_own_file(cow, tmp_path):
    with pytest.raises(dfm.UnsupportedError, match="FBX is written only back into the FBX file"):
        cow.save(tmp_path / "cow.fbx")
    assert not (tmp_path / "cow.fbx").exists()
