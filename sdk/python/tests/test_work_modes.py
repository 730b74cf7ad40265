"""The work modes from Python: the context's pool, a job system of Python
threads (JobQueue), and host stepping give the same bits; the host's modes
start no thread in the library; deform_batch solves many edits at once,
each as a session of its own would."""

from __future__ import annotations

import os

import numpy as np
import pytest

import dualform as dfm


def hoof_targets(cow, hoof, count: int) -> list:
    rest = cow.positions()[hoof.vertices()]
    diagonal = cow.info.diagonal
    return [rest + np.array([0.01 * (i + 1), 0.004 * i, -0.003 * i]) * diagonal
            for i in range(count)]


def drag(ctx: dfm.Context, steps: int = 4) -> np.ndarray:
    with dfm.Mesh.load(ctx, "model:cow") as cow, cow.water_fill(771, 681) as leg, \
            cow.roi_ball(771, 0.03) as hoof, dfm.Session(cow, leg, [hoof.vertices()]) as session:
        for t in hoof_targets(cow, hoof, steps):
            session.set_targets(t)
            info = session.wait(session.submit())
            assert info.converged
        return session.read_roi_positions()[0]


def process_threads() -> int:
    return len(os.listdir("/proc/self/task"))


def library_workers() -> int:
    """The process's threads named as the context's workers are."""
    count = 0
    for task in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{task}/comm") as comm:
                count += comm.read().strip() == "dfm-worker"
        except FileNotFoundError:  # a thread that ended since the listing
            pass
    return count


def test_the_modes_give_the_same_bits():
    with dfm.Context() as ctx:
        pooled = drag(ctx)
    with dfm.JobQueue(2) as jobs, \
            dfm.Context(work_mode=dfm.WorkMode.JOB_SYSTEM, job_system=jobs, worker_count=2) as ctx:
        assert ctx.work_mode is dfm.WorkMode.JOB_SYSTEM
        handed = drag(ctx)
    with dfm.Context(work_mode=dfm.WorkMode.HOST_STEPPED) as ctx:
        stepped = drag(ctx)
        assert ctx.step() is False
    assert pooled.tobytes() == handed.tobytes()
    assert pooled.tobytes() == stepped.tobytes()


def test_steps_run_the_work_within_a_budget(cow):
    with dfm.Context(work_mode=dfm.WorkMode.HOST_STEPPED) as ctx, \
            dfm.Mesh.load(ctx, "model:cow") as mesh, mesh.water_fill(771, 681) as leg, \
            mesh.roi_ball(771, 0.03) as hoof, dfm.Session(mesh, leg, [hoof.vertices()]) as session:
        session.set_targets(hoof_targets(mesh, hoof, 1)[0])
        generation = session.submit()
        info, _ = session.poll()
        assert info.preparing
        steps = 1
        while ctx.step(budget_us=1):
            steps += 1
        assert steps > 2  # the set-up, then the solve an iteration at a time
        done = session.wait(generation, timeout=0)
        assert done.generation == generation and done.converged
        with pytest.raises(dfm.UnsupportedError):
            cow.context.step()


def test_the_host_modes_start_no_thread():
    with dfm.JobQueue(2) as jobs:
        before = process_threads()
        with dfm.Context(work_mode=dfm.WorkMode.JOB_SYSTEM, job_system=jobs,
                         worker_count=2) as ctx:
            drag(ctx, steps=2)
            assert process_threads() == before
        with dfm.Context(work_mode=dfm.WorkMode.HOST_STEPPED) as ctx:
            drag(ctx, steps=2)
            assert process_threads() == before
    # Counted by name: a thread of the job queue, joined above, can still be
    # listed for a moment after Python's join returns.
    with dfm.Context(worker_count=2):
        assert library_workers() == 2


@pytest.mark.parametrize("mode", list(dfm.WorkMode))
def test_deform_batch_gives_each_edit_its_own_sessions_result(mode):
    jobs = dfm.JobQueue(2) if mode is dfm.WorkMode.JOB_SYSTEM else None
    try:
        workers = 1 if mode is dfm.WorkMode.HOST_STEPPED else 2
        with dfm.Context(work_mode=mode, job_system=jobs, worker_count=workers) as ctx, \
                dfm.Mesh.load(ctx, "model:cow") as cow, cow.water_fill(771, 681) as leg, \
                cow.roi_ball(771, 0.03) as hoof:
            targets = hoof_targets(cow, hoof, 6)
            batch = dfm.deform_batch(cow, leg, [hoof.vertices()], targets, chunk=4)
            assert batch.shape == (6, len(leg), 3)
            for i in (0, 5):
                with dfm.Session(cow, leg, [hoof.vertices()]) as alone:
                    alone.set_targets(targets[i])
                    alone.wait(alone.submit())
                    assert alone.read_roi_positions()[0].tobytes() == batch[i].tobytes()
            with pytest.raises(ValueError):
                dfm.deform_batch(cow, leg, [hoof.vertices()], targets, chunk=0)
    finally:
        if jobs is not None:
            jobs.close()
