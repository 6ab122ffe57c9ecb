"""The lighting equation's arithmetic (roughlight.render.shading)."""

import numpy as np
import pytest

from roughlight.render import shading
from roughlight.render.shading import Lighting


@pytest.mark.parametrize("model", ["phong", "blinn"])
@pytest.mark.parametrize("n_facets", [10, 512])
def test_the_specular_is_the_same_to_the_bit_as_summed_over_a_products_array(model, n_facets):
    """facet_values sums each view's and facet's dot product without a (views, facets, 3) array of products (a
    random tile's made it 0.1 s a sweep). The sums must be those of np.sum(a * b, axis=-1), to the bit: a last
    bit moved can move an 8-bit value, and the regular sweeps are to stay what they were."""
    rng = np.random.default_rng(7)
    normals = rng.normal(size=(n_facets, 3)) * [0.5, 0.5, 1.0] + [0.0, 0.0, 2.0]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    elevation, azimuth = np.meshgrid(np.arange(0.0, 181.0, 3.0), np.arange(0.0, 180.0, 15.0))
    views = shading.view_direction(elevation.ravel(), azimuth.ravel())
    light = shading.light_direction(30.0)
    lighting = Lighting(light=127.0, specular_reflectance=0.8, shininess=64.0, specular_model=model)
    (_, specular, _), _ = shading.facet_values(normals, light, views, lighting, quantized=False)

    n, v = normals[None, :, :], views[:, None, :]
    ndotl = np.sum(n * light, axis=-1)
    if model == "phong":
        base = np.sum((2.0 * ndotl[..., None] * n - light) * v, axis=-1)
    else:
        h = light + v
        base = np.sum(n * (h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-12)), axis=-1)
    facing = ndotl > 0
    expected = 127.0 * facing.astype(float) * 0.8 * np.where(facing, np.maximum(base, 0.0) ** 64.0, 0.0)
    assert np.array_equal(specular, expected)
    assert np.count_nonzero(expected) > expected.size // 10  # something lit
