"""Many worlds in one Simulator (rigid.engine.worlds): each world is the scene run alone.

The reference is the same scene in a Simulator of its own, one world, the same values, on the
same schedule (more particles may otherwise choose the parallel one, whose sums agree with the
serial one's to round-off): every world's rows must equal it bit for bit (the same operations
on the same numbers, whatever the other worlds do). Identical copies placed at the same spot also show that no contact crosses
worlds: a body meeting its twin of another world would be thrown apart at once.
"""
import numpy as np
import pytest

from conftest import ASSETS

SCENES = ASSETS / "scenes"
KEYS = ("x", "q", "v", "omega", "P", "L")


def _load(name, **changes):
    from rigid.config import SimConfig, load_scene

    return SimConfig(**{**load_scene(SCENES / name), **changes}).validate()


def _sim(units, config, schedule="serial", **kwargs):
    from rigid.engine.simulator import Simulator

    return Simulator(config, units, schedule=schedule, **kwargs)


def _assert_world_is_alone(rows, w, alone):
    for key in KEYS:
        np.testing.assert_array_equal(rows[key][:, w], alone[key], err_msg=key)
    for key in ("kinetic_energy", "potential_energy"):
        np.testing.assert_array_equal(rows[key][:, w], alone[key], err_msg=key)


def test_thrown_spheres_each_follow_their_own_throw(units):
    config = _load("thrown_sphere.toml")
    throws = np.array(config.initial_velocity) * np.array([[0.5], [1.0], [1.3]])
    rows = _sim(units, config, worlds=3, vary={"initial_velocity": throws}).advance(40)
    assert rows["x"].shape == (41, 3, 1, 3) and rows["kinetic_energy"].shape == (41, 3)
    for w in range(3):
        alone = _sim(units, config.replace(initial_velocity=tuple(throws[w]))).advance(40)
        _assert_world_is_alone(rows, w, alone)
    assert len({float(rows["x"][-1, w, 0, 0]) for w in range(3)}) == 3, "each world its own flight"


@pytest.mark.parametrize("worlds", [2, 40])
def test_colliding_bodies_touch_only_their_own_worlds(units, worlds):
    """head_on: two spheres meet and part; every world starts at the same spot, and with 40 the
    grid wraps, so cells hold other worlds' particles, which the lists must pass over."""
    config = _load("head_on.toml")
    alone = _sim(units, config).advance(50)
    before, after = alone["v"][0, :, 0], alone["v"][-1, :, 0]
    assert np.all(np.sign(before) != np.sign(after)), "the spheres should have collided and parted"
    rows = _sim(units, config, worlds=worlds).advance(50)
    for w in (0, worlds // 2, worlds - 1):
        _assert_world_is_alone(rows, w, alone)


def test_worlds_with_materials_and_springs_follow_their_scene_alone(units):
    for name in ("bounce.toml", "chain.toml"):
        config = _load(name)
        alone = _sim(units, config).advance(30)
        rows = _sim(units, config, worlds=2).advance(30)
        for w in range(2):
            _assert_world_is_alone(rows, w, alone)


def test_the_parallel_schedule_runs_many_worlds_as_it_runs_one(units):
    config = _load("head_on.toml")
    alone = _sim(units, config, schedule="parallel").advance(40)
    rows = _sim(units, config, schedule="parallel", worlds=3).advance(40)
    for w in range(3):
        for key in KEYS:
            np.testing.assert_allclose(rows[key][:, w], alone[key], rtol=0, atol=1e-5, err_msg=key)


@pytest.mark.parametrize("worlds, vary, words", [
    (0, None, "worlds must be a whole number >= 1"),
    (2, {"gravity": [[0, -9.8, 0]] * 2}, "'gravity' cannot differ between worlds"),
    (2, {"initial_velocity": [[1, 2, 3]] * 3}, "'initial_velocity' has shape (3, 3); give (2, 3)"),
    (2, {"particle_mass": [1.0, -1.0]}, "'particle_mass' must be > 0"),
])
def test_bad_worlds_or_vary_are_one_line(units, worlds, vary, words):
    from rigid.errors import UserError

    with pytest.raises(UserError) as error:
        _sim(units, _load("thrown_sphere.toml"), worlds=worlds, vary=vary)
    assert words in str(error.value) and "\n" not in str(error.value)
