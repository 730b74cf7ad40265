"""Sessions: staging, solving on the worker or this thread, frames, bakes."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

import dualform as dfm


@pytest.fixture()
def leg(cow):
    roi = cow.water_fill(771, 681)
    with cow.roi_ball(771, 0.03) as hoof:
        hoof_vertices = hoof.vertices()
    with roi:
        yield cow, roi, hoof_vertices


def test_async_and_sync_agree_bit_for_bit(leg):
    cow, roi, hoof = leg
    offset = np.array([0.08, 0.03, 0.0]) * cow.info.diagonal
    with dfm.Session(cow, roi, [hoof]) as a, dfm.Session(cow, roi, [hoof]) as b:
        a.set_translation(0, offset)
        generation = a.submit()
        info = a.wait(generation)
        assert info.converged and not info.partial and info.status == 0
        b.set_targets(cow.positions()[hoof] + offset)
        b.solve()
        pa, ia = a.read_positions()
        pb, ib = b.read_positions()
        assert np.array_equal(pa, pb) and ia.checksum == ib.checksum
        moved = np.linalg.norm(pa - cow.positions(), axis=1)
        assert moved[771] > 0.05 and moved[np.setdiff1d(np.arange(len(pa)), roi.vertices())].max() == 0


def test_frames_poll_roi_reads_and_zero_copy_view(leg):
    cow, roi, hoof = leg
    with dfm.Session(cow, roi, [hoof]) as s:
        s.set_translation(0, [0.05, 0.0, 0.0])
        g = s.submit()
        s.wait(g)
        info, is_new = s.poll(0)
        assert is_new and info.generation == g
        assert s.poll(g)[1] is False
        roi_positions, _ = s.read_roi_positions()
        assert dfm.frame_checksum(roi_positions) == info.checksum
        with s.acquire_frame() as frame:
            assert frame.info.generation == g
            assert not frame.roi_positions_f64.flags.owndata
            assert not frame.roi_positions_f64.flags.writeable
            assert np.array_equal(frame.roi_positions_f64, roi_positions)
            assert np.array_equal(frame.roi_vertices, roi.vertices())
            assert frame.normals.shape == (len(frame.normal_vertices), 3)
        normals, _ = s.read_normals(np.float32)
        assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
        quality, _ = s.measure_quality()
        assert quality.max_fixed_move == 0.0 and quality.max_handle_error < 0.01
        report, _ = s.solve_report()
        assert report.unknowns > 0
        assert s.memory.total > 0 and s.handle_count == len(hoof)


def test_group_transform_is_column_major_of_the_numpy_matrix(leg):
    cow, roi, hoof = leg
    angle = np.radians(30.0)
    m = np.eye(4)
    m[:3, :3] = [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    m[:3, 3] = [0.01, 0.02, 0.0]
    rest = cow.positions()[hoof]
    with dfm.Session(cow, roi, [hoof], hard_handles=True) as s:
        s.set_group_transform(0, m)
        s.solve()
        p, _ = s.read_positions()
        assert np.allclose(p[hoof], rest @ m[:3, :3].T + m[:3, 3], atol=1e-9)


def test_on_frame_hears_every_published_frame(leg):
    cow, roi, hoof = leg
    heard = []
    with dfm.Session(cow, roi, [hoof], on_frame=lambda s, info: heard.append(info)) as s:
        s.set_translation(0, [0.05, 0.0, 0.0])
        g = s.submit()
        s.wait(g)
    assert any(i.generation == g and not i.partial for i in heard)


def test_bake_undo_redo(leg):
    cow, roi, hoof = leg
    rest = cow.positions()
    with dfm.Session(cow, roi, [hoof]) as s:
        s.set_translation(0, [0.05, 0.0, 0.0])
        s.wait(s.submit())
        solved, _ = s.read_positions()
        s.bake()
    assert np.array_equal(cow.positions(), solved) and cow.info.bake_count == 1
    cow.undo_bake()
    assert np.array_equal(cow.positions(), rest)
    cow.redo_bake()
    assert np.array_equal(cow.positions(), solved)


def test_waiting_releases_the_gil():
    # The context's work goes to a job system that runs nothing until this
    # thread runs it, so a thread waiting for the set-up waits in the
    # library until then. This thread must go on running Python meanwhile:
    # it sees the session preparing, then hands the jobs over. Were the GIL
    # held by the wait, this thread would stop at its next bytecode and the
    # wait would never end.
    held = []
    with dfm.Context(work_mode=dfm.WorkMode.JOB_SYSTEM, job_system=held.append) as ctx, \
            dfm.Mesh.load(ctx, "model:cow") as cow, cow.roi_ball(771, 0.3) as roi, \
            dfm.Session(cow, roi, [[771]]) as s:
        done = threading.Event()

        def waiter():
            s.wait()
            done.set()

        t = threading.Thread(target=waiter)
        t.start()
        try:
            time.sleep(0.2)  # the waiter is in the library by now, holding nothing
            info, _ = s.poll()
            assert info.preparing and not done.is_set()
        finally:
            # The jobs handed over are run whatever happened: the context
            # waits for them when it closes.
            while not done.is_set():
                while held:
                    dfm.run_job(held.pop(0))
                time.sleep(0.001)
            t.join()
        assert not s.poll()[0].preparing


def test_a_failed_solve_raises_unless_the_frame_is_asked_for(leg):
    cow, roi, hoof = leg
    with dfm.Session(cow, roi, [hoof]) as s:
        s.set_translation(0, [1e300, 0.0, 0.0])
        g = s.submit()
        with pytest.raises(dfm.NumericalError) as caught:
            s.wait(g)
        assert f"generation {g}: the solve failed" in caught.value.message
        frame = caught.value.frame
        assert frame.status is dfm.Result.ERROR_NUMERICAL and not frame.converged
        info = s.wait(g, check_status=False)
        assert info.status is dfm.Result.ERROR_NUMERICAL and info.generation == g
        # The frame keeps the last good (here: the rest) positions.
        positions, read = s.read_positions()
        assert read.status is dfm.Result.ERROR_NUMERICAL
        assert np.array_equal(positions, cow.positions())
        with pytest.raises(dfm.NumericalError):
            s.solve()
        s.set_translation(0, [0.01, 0.0, 0.0])
        assert s.wait(s.submit()).status is dfm.Result.OK
