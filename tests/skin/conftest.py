"""The rigged assets, each loaded and matched to Blender's vertices once."""

from __future__ import annotations

import pytest

from rigged import SKINNED, Rigged

_loaded: dict[str, Rigged] = {}


@pytest.fixture(params=SKINNED)
def rigged(request) -> Rigged:
    if request.param not in _loaded:
        _loaded[request.param] = Rigged(request.param)
    return _loaded[request.param]
