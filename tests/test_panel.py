"""The window's control panel without a window: a stand-in GUI moves the sliders and presses buttons."""
import contextlib

import numpy as np


class FakeGui:
    """Answers like GGUI's imgui: sliders return ``moves[label]`` if given, else the old value."""

    def __init__(self, moves=None, press=()):
        self.moves, self.press, self.texts = moves or {}, set(press), []

    @contextlib.contextmanager
    def sub_window(self, name, x, y, width, height):
        yield self

    def text(self, text, color=None):
        self.texts.append(text)

    def slider_float(self, label, old, minimum, maximum):
        return float(np.float32(self.moves.get(label, old)))  # imgui works in float32

    def checkbox(self, label, old):
        return old

    def button(self, label):
        return label in self.press


def test_untouched_sliders_change_nothing(sim_cache):
    from rigid.view.panel import ControlPanel

    sim = sim_cache()
    before = {n: float(getattr(sim.params, n)) for n in sim.params.NAMES}
    pressed = ControlPanel(sim).draw(FakeGui(), fps=60.0)
    assert not pressed["params_changed"] and not pressed["reset"]
    assert {n: float(getattr(sim.params, n)) for n in sim.params.NAMES} == before


def test_gravity_slider_takes_effect_on_the_next_frame(sim_cache):
    from rigid.view.panel import ControlPanel

    sim = sim_cache(walls=False)
    pressed = ControlPanel(sim).draw(FakeGui({"gravity y": -20.0, "dt [ms]": 0.5}), fps=60.0)
    assert pressed["params_changed"]
    assert sim.substeps == 33  # int(1/60 // 0.5e-3)
    for _ in range(3):
        sim.step_frame()
    # free fall from rest: v_y = g t with the new g (exact for Euler's momentum update)
    np.testing.assert_allclose(sim.snapshot()["v"][0], [0.0, -20.0 * sim.time, 0.0], rtol=1e-4, atol=1e-6)


def test_kick_button_gives_momentum_and_spin(sim_cache):
    from rigid.view.panel import KICK_SPEED, ControlPanel

    sim = sim_cache(gravity=(0, 0, 0), walls=False)
    panel = ControlPanel(sim, seed=3)
    pressed = panel.draw(FakeGui(press={"random kick (k)"}), fps=60.0)
    assert pressed["kick"]
    panel.kick()
    snap = sim.snapshot()
    assert np.isclose(np.linalg.norm(snap["v"]), KICK_SPEED, rtol=1e-5)  # |J| = M · KICK_SPEED
    assert np.linalg.norm(snap["L"]) > 0.1  # off-centre: it spins
