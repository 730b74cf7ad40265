"""Every handle is freed exactly once: the counting allocator, which serves
every object behind a handle, holds nothing once they are all closed."""

from __future__ import annotations

import gc

import numpy as np

import dualform as dfm
from conftest import tetrahedron


def edit_everything(ctx: dfm.Context) -> None:
    with dfm.Mesh.load(ctx, "model:cow") as cow:
        roi = cow.water_fill(771, 681)
        hoof = cow.roi_ball(771, 0.03)
        with roi, hoof, roi.boundary() as fixed, roi.grow(1):
            assert len(fixed) > 0
            with dfm.Session(cow, roi, [hoof.vertices()]) as s:
                s.set_translation(0, [0.05, 0.0, 0.0])
                s.wait(s.submit())
                with s.acquire_frame():
                    pass
                s.bake()
            # Destroyed while its set-up runs.
            dfm.Session(cow, roi, [hoof.vertices()]).close()
        cow.undo_bake()
        with cow.subdivide(1) as fine:
            assert fine.vertex_count > cow.vertex_count
    positions, triangles = tetrahedron()
    mesh = dfm.Mesh.from_arrays(ctx, positions.astype(np.float32), triangles)
    mesh.close()
    mesh.close()


def test_all_handles_freed():
    allocator = dfm.CountingAllocator()
    ctx = dfm.Context(allocator=allocator)
    edit_everything(ctx)
    assert allocator.outstanding > 0  # the context itself
    ctx.close()
    assert allocator.allocations > 1
    assert allocator.outstanding == 0
    assert allocator.frees == allocator.allocations
    assert allocator.mismatched_frees == 0


def test_a_forgotten_handle_is_counted_then_freed_by_the_collector():
    allocator = dfm.CountingAllocator()
    with dfm.Context(allocator=allocator) as ctx:
        baseline = allocator.outstanding
        forgotten = dfm.Mesh.load(ctx, "model:cow")
        assert allocator.outstanding > baseline
        del forgotten
        gc.collect()
        assert allocator.outstanding == baseline
    assert allocator.outstanding == 0


def test_a_mesh_outlives_its_closed_context():
    allocator = dfm.CountingAllocator()
    ctx = dfm.Context(allocator=allocator)
    mesh = dfm.Mesh.load(ctx, "model:cow")
    ctx.close()
    assert mesh.info.vertex_count == 2904
    assert allocator.outstanding > 0
    mesh.close()
    assert allocator.outstanding == 0
