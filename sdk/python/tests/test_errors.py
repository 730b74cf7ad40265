"""Every failing call raises the DualformError subclass of its dfm_result,
with the C API's own message."""

from __future__ import annotations

import numpy as np
import pytest

import dualform as dfm
from conftest import tetrahedron


def test_missing_file_names_it(context):
    with pytest.raises(dfm.NotFoundError) as caught:
        dfm.Mesh.load(context, "/no/such/mesh.off")
    e = caught.value
    assert e.result == 2 and e.name == "DFM_ERROR_NOT_FOUND"
    assert "/no/such/mesh.off" in e.message
    assert dfm.result_name(e.result) == e.name


def test_parse_error_names_the_place(context, tmp_path):
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n")
    with pytest.raises(dfm.ParseError) as caught:
        dfm.Mesh.load(context, bad)
    assert "bad.off" in caught.value.message and ":" in caught.value.message


def test_index_out_of_range_names_triangle_and_corner(context):
    positions, triangles = tetrahedron()
    triangles = triangles.copy()
    triangles[2, 1] = 9
    with pytest.raises(dfm.DualformError) as caught:
        dfm.Mesh.from_arrays(context, positions, triangles)
    assert caught.value.name in ("DFM_ERROR_OUT_OF_RANGE", "DFM_ERROR_INVALID_ARGUMENT")
    assert "2" in caught.value.message and "9" in caught.value.message


def test_non_finite_position_is_numerical(context):
    positions, triangles = tetrahedron()
    positions = positions.copy()
    positions[3, 0] = np.nan
    with pytest.raises(dfm.DualformError) as caught:
        dfm.Mesh.from_arrays(context, positions, triangles)
    assert "3" in caught.value.message


def test_handle_outside_roi_names_group_and_vertex(cow):
    with cow.roi_ball(771, 0.05) as roi:
        outside = int(np.setdiff1d(np.arange(cow.vertex_count), roi.vertices())[0])
        with pytest.raises(dfm.InvalidArgumentError) as caught:
            dfm.Session(cow, roi, [[771], [outside]])
    assert str(outside) in caught.value.message


def test_closed_handle_raises_invalid_handle(context):
    positions, triangles = tetrahedron()
    mesh = dfm.Mesh.from_arrays(context, positions, triangles)
    mesh.close()
    mesh.close()
    with pytest.raises(dfm.InvalidHandleError):
        mesh.info


def test_wrong_shape_and_dtype_refused_before_the_call(context):
    positions, triangles = tetrahedron()
    with pytest.raises(ValueError):
        dfm.Mesh.from_arrays(context, positions[:, :2], triangles)
    with pytest.raises(TypeError):
        dfm.Mesh.from_arrays(context, positions, triangles.astype(np.float32))


def test_second_acquire_is_busy_and_wait_times_out(cow):
    with cow.water_fill(771, 681) as roi, dfm.Session(cow, roi, [[771]]) as session:
        session.wait()
        with session.acquire_frame():
            with pytest.raises(dfm.BusyError) as caught:
                with session.acquire_frame():
                    pass
            assert caught.value.message
        with pytest.raises(dfm.InvalidArgumentError) as caught:
            session.wait(5)
        assert "never submitted" in caught.value.message


def test_wait_times_out_while_the_set_up_runs():
    # The context's work goes to a job system that runs nothing until this
    # thread runs it, so the set-up is still to do when the wait is asked.
    held = []
    with dfm.Context(work_mode=dfm.WorkMode.JOB_SYSTEM, job_system=held.append) as ctx, \
            dfm.Mesh.load(ctx, "model:cow") as cow, cow.roi_ball(771, 0.3) as roi, \
            dfm.Session(cow, roi, [[771]]) as session:
        session.set_translation(0, [0.05, 0, 0])
        generation = session.submit()
        try:
            with pytest.raises(dfm.BusyError):
                session.wait(generation, timeout=0)
        finally:
            # The jobs handed over are run whatever happened: the context
            # waits for them when it closes.
            while True:
                while held:
                    dfm.run_job(held.pop(0))
                try:
                    info = session.wait(generation, timeout=0.001)
                    break
                except dfm.BusyError:
                    pass
        assert info.generation == generation


def test_undo_with_nothing_to_undo_is_not_found(cow):
    with pytest.raises(dfm.NotFoundError) as caught:
        cow.undo_bake()
    assert caught.value.message


def test_a_negative_index_is_refused_before_the_call(cow):
    with pytest.raises(ValueError) as caught:
        cow.water_fill(-1, 681)
    assert str(caught.value) == ("first: expected a vertex index, an integer from 0 to "
                                 "4294967294, found -1")
    with pytest.raises(ValueError, match="center: .* found -5"):
        cow.roi_ball(-5, 0.1)
    with pytest.raises(ValueError, match="steps: .* found -1"):
        cow.subdivide(-1)


def test_a_matrix_that_is_not_affine_is_refused(cow):
    with cow.water_fill(771, 681) as roi, dfm.Session(cow, roi, [[771]]) as session:
        with pytest.raises(dfm.InvalidArgumentError) as caught:
            session.set_group_transform(0, np.zeros((4, 4)))
        assert "bottom row" in caught.value.message and "found 0 0 0 0" in caught.value.message
        row_major = np.eye(4)
        row_major[3, :3] = [0.1, 0.0, 0.0]
        with pytest.raises(dfm.InvalidArgumentError, match="found 0.1 0 0 1"):
            session.set_group_transform(0, row_major)
        with pytest.raises(ValueError, match="group: .* found -1"):
            session.set_group_transform(-1, np.eye(4))


def test_results_are_an_enum_named_as_in_c(context):
    assert dfm.Result.ERROR_NUMERICAL == 8 and str(dfm.Result.ERROR_NUMERICAL) == \
        "DFM_ERROR_NUMERICAL"
    assert [str(r) for r in dfm.Result] == [dfm.result_name(int(r)) for r in dfm.Result]
    with pytest.raises(dfm.NotFoundError) as caught:
        dfm.Mesh.load(context, "/no/such/mesh.off")
    assert caught.value.result is dfm.Result.ERROR_NOT_FOUND
    assert dfm.NumericalError.result is dfm.Result.ERROR_NUMERICAL
