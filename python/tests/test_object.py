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


def bakes_probes():
    """Whether this module's bake() takes probes= (issue 37's bake half)."""
    return "probes: " in (shprt.bake.__doc__ or "")


@needs_render
@pytest.mark.skipif(not bakes_probes(), reason="this shprt bakes no probes (bake(probes=...))")
def test_an_object_is_darker_in_the_boxs_shadow_than_on_its_sunlit_side(box, tmp_path):
    """builtin:box_on_plane baked with probes, under a sun in +x projected into SH: seen from
    above, the object beside the box is darker on its shadow side (−x) than on its sunlit side (+x),
    the mirror position."""
    path = str(tmp_path / "box.shprt")
    shprt.bake(box, bands=3, samples=128, probes=(8, 2, 8), output=path)
    f = shprt.load(path)
    L = shprt.light("sun:1,0.6,0", K=9)
    camera = (0, 5, 0.01, 0, 0, 0)
    bare = shprt.render(f, L, width=128, height=96, samples=1, camera=camera)
    means = []
    for x in (0.9, -0.9):
        img = shprt.render(f, L, width=128, height=96, samples=1, camera=camera,
                           object="builtin:sphere", at=(x, 0.3, 0), object_scale=0.3)
        mask = (img != bare).any(axis=2)
        assert mask.sum() > 50
        means.append(float(img[mask].mean()))
    assert means[0] > 1.5 * means[1], means
    with pytest.warns(UserWarning, match="is outside the probe grid"):
        shprt.render(f, L, width=16, height=16, samples=1, object="builtin:sphere",
                     at=(9, 0.3, 0), object_scale=0.25)
