"""Soft contact shadows: darkest under a body resting on the floor, fading and spreading as it
rises, none far from it; the same picture on every run."""
import numpy as np


def test_a_shadow_under_a_body_fades_with_height_and_the_picture_is_reproducible(sim_cache):
    from rigid.view.render import SceneRenderer
    from rigid.view.shadow import DARKEST

    sim = sim_cache()  # the sphere, radius 0.3, at the origin: its lowest point 0.7 m above the floor
    renderer = SceneRenderer(sim, (160, 90), offscreen=True)
    shadows = renderer.shadows
    grid = shadows.shade.to_numpy

    import taichi as ti

    x = ti.ndarray(ti.types.vector(3, ti.f32), 1)
    R = ti.ndarray(ti.types.matrix(3, 3, ti.f32), 1)
    R.from_numpy(np.eye(3, dtype=np.float32)[None])

    def shade_under(height_of_centre):
        x.from_numpy(np.array([[0.2, -1.0 + height_of_centre, -0.1]], np.float32))
        shadows.update(x, R)
        shade = grid()
        i, k = (np.array([0.2, -0.1]) + 1.0) / 2.0 * shade.shape[0]
        return shade[int(i), int(k)], shade[0, 0]

    resting, corner = shade_under(0.3)  # touching the floor
    assert corner == 1.0  # far from the body: no shadow
    assert 1.0 - DARKEST - 0.05 < resting < 1.0 - 0.8 * DARKEST  # dark under its middle
    high, _ = shade_under(1.3)
    assert resting < high < 1.0  # fainter, but still there, a metre up
    renderer.draw()
    first = renderer.read_rgba()
    renderer.draw()
    assert np.array_equal(first, renderer.read_rgba())
    plain = SceneRenderer(sim, (160, 90), offscreen=True)
    plain.shadows = None
    plain.draw()
    unshadowed = plain.read_rgba()[..., :3].astype(int).sum(axis=2)
    shadowed = first[..., :3].astype(int).sum(axis=2)
    assert (shadowed <= unshadowed).all() and (shadowed < unshadowed - 30).sum() > 20  # darker under the body only
