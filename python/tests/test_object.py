"""render(object=..., at=...): a mesh lit from the file's transfer probes (docs/probes.md,
"Lighting objects"). Its placement is checked before anything is read, a file without probes is
refused by name, as `shprt render --object` does."""
import pytest

import shprt

needs_render = pytest.mark.skipif(not shprt.HAS_RENDER,
                                  reason="this build has no renderer (shprt.render)")


@pytest.fixture(scope="module")
def no_probes(box):
    return shprt.File(box, shprt.bake(box, bands=3, samples=16))


@needs_render
def test_a_file_without_probes_is_refused(no_probes):
    L = shprt.light("builtin", K=9)
    with pytest.raises(shprt.Error, match="has no transfer probes"):
        shprt.render(no_probes, L, width=16, height=16, object="builtin:sphere", at=(0, 0.5, 0))


@needs_render
@pytest.mark.parametrize("kwargs, message", [
    (dict(object="builtin:sphere"), "give its position with at="),
    (dict(at=(0, 0, 0)), "give object=MESH"),
    (dict(object_scale=2.0), "give object=MESH"),
    (dict(object="builtin:sphere", at=(0, 0, 0), object_scale=0.0), "object_scale=0"),
    (dict(object="builtin:sphere", at=(0, 0, float("nan"))), "must be finite"),
])
def test_the_placement_is_checked_first(no_probes, kwargs, message):
    L = shprt.light("builtin", K=9)
    with pytest.raises(shprt.Error, match=message):
        shprt.render(no_probes, L, width=16, height=16, **kwargs)
