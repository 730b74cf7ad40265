"""A drag in Python: one thread stages and submits a moving target per
step while another reads frames. Every frame read is whole (its checksum
matches its positions) and generations never go back."""

from __future__ import annotations

import threading

import numpy as np

import dualform as dfm


def test_drag_loop_with_a_reader_thread(cow):
    steps = 150
    with cow.water_fill(771, 681) as roi, cow.roi_ball(771, 0.03) as hoof, \
            dfm.Session(cow, roi, [hoof.vertices()]) as session:
        session.wait()
        done = threading.Event()
        failures = []
        seen = []

        def reader():
            buffer = np.empty((len(roi), 3))
            while not done.is_set() or not seen or seen[-1] < steps:
                positions, info = session.read_roi_positions(out=buffer)
                if dfm.frame_checksum(positions) != info.checksum:
                    failures.append(f"torn frame at generation {info.generation}")
                if seen and info.generation < seen[-1]:
                    failures.append(f"generation {info.generation} after {seen[-1]}")
                seen.append(info.generation)
                with session.acquire_frame() as frame:
                    if frame.info.generation < seen[-1]:
                        failures.append("a lent frame older than the one read before")

        t = threading.Thread(target=reader)
        t.start()
        diagonal = cow.info.diagonal
        last = 0
        for step in range(1, steps + 1):
            session.set_translation(0, [0.1 * diagonal * step / steps, 0.0, 0.0])
            last = session.submit()
        final = session.wait(last)
        done.set()
        t.join(timeout=60)
        assert not t.is_alive()
        assert failures == []
        assert final.generation == steps and final.converged
        assert seen[-1] == steps and len(seen) > 1
        positions, info = session.read_positions()
        assert info.generation == steps

    # The same final targets solved from the start agree to the tolerance.
    with cow.water_fill(771, 681) as roi, cow.roi_ball(771, 0.03) as hoof, \
            dfm.Session(cow, roi, [hoof.vertices()]) as fresh:
        fresh.set_translation(0, [0.1 * diagonal, 0.0, 0.0])
        fresh.solve()
        direct, _ = fresh.read_positions()
    assert np.abs(direct - positions).max() < 1e-3 * diagonal
