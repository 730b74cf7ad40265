"""Many edits of one region at once, across the context's workers."""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from .mesh import Mesh, Roi
from .session import Session


def deform_batch(mesh: Mesh, roi: Roi, groups: Sequence[Sequence[int]], targets: Sequence,
                 *, chunk: Optional[int] = None, **solver) -> np.ndarray:
    """Solves one edit per entry of ``targets`` (each ``(handle_count, 3)``,
    in group order) on ``roi`` with handle ``groups``, and returns the
    converged ROI positions of each, ``(len(targets), len(roi), 3)`` float64.

    Each edit is a session of its own, started from the rest pose, so its
    result is bit for bit what one session solving it alone gives, whatever
    runs it. ``chunk`` sessions at a time (default: all) are created, staged
    and submitted before any is waited for: their set-ups and solves take
    turns on the context's workers (its threads, the host's job system, or,
    stepped, the waits themselves). A solve that fails raises its error.
    ``solver`` takes :class:`Session`'s solver settings."""
    edits = [np.asarray(t, dtype=np.float64) for t in targets]
    out = np.empty((len(edits), len(roi), 3), dtype=np.float64)
    size = len(edits) if chunk is None else chunk
    if size < 1:
        raise ValueError(f"chunk: expected at least 1, found {size}")
    for first in range(0, len(edits), size):
        sessions = []
        try:
            for t in edits[first:first + size]:
                session = Session(mesh, roi, groups, **solver)
                sessions.append(session)
                session.set_targets(t)
            generations = [s.submit() for s in sessions]
            for i, (s, g) in enumerate(zip(sessions, generations)):
                s.wait(g)
                s.read_roi_positions(out=out[first + i])
        finally:
            for s in sessions:
                s.close()
    return out
