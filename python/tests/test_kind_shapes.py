"""Every transfer kind's array shape from Python (the kind table's receiver_shape,
transfer/kind_table.hpp): what bake() returns for a kind is what File(kind=...) takes back, and
the file's K and channels are the kind's."""
import numpy as np
import pytest

import shprt

# kind -> (channels, floats per channel at bands=2: K = 4)
KINDS = {
    "unshadowed": (1, 4),
    "shadowed": (1, 4),
    "interreflected": (3, 4),
    "glossy": (1, 10),
}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_baked_array_is_its_kinds_shape_and_makes_a_file(box, kind):
    channels, floats = KINDS[kind]
    T = shprt.bake(box, bands=2, samples=16, transfer=kind, seed=5)
    V = box.vertex_count
    assert T.shape == ((V, floats) if channels == 1 else (V, channels, floats))
    f = shprt.File(box, T, kind=kind, samples=16, seed=5)
    assert (f.kind, f.K, f.channels) == (kind, 4, channels)
    np.testing.assert_array_equal(f.transfer, T)
