"""report/quickstart.ipynb, executed headless by nbclient: it builds a scene, runs it, shows the run
inline as a video drawn by the software renderer, plots the energy, and returns frames as arrays."""
import base64
import io
import re

import numpy as np
import pytest

from conftest import ROOT

NOTEBOOK = ROOT / "report" / "quickstart.ipynb"


def executed(path):
    """The notebook at ``path`` (stored without outputs) run headless from the repository's root:
    its outputs, none an error, and the text it printed."""
    nbformat = pytest.importorskip("nbformat", reason="the dev extra installs nbformat, nbclient, ipykernel")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    nb = nbformat.read(path, as_version=4)
    assert not any(cell.get("outputs") for cell in nb.cells if cell.cell_type == "code")  # stored without outputs
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(ROOT)}}).execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    return outputs, "".join(o.get("text", "") for o in outputs if o.output_type == "stream")


def test_the_quickstart_notebook_runs_and_shows_a_video_a_plot_and_frames():
    outputs, text = executed(NOTEBOOK)
    assert "1 body, 42 particles, 16 substeps a frame" in text

    html = [o.data["text/html"] for o in outputs if o.output_type == "execute_result" and "text/html" in o.data]
    assert len(html) == 1 and html[0].startswith("<video")
    mp4 = base64.b64decode(re.search(r"base64,([A-Za-z0-9+/=]+)", html[0]).group(1))
    import av

    with av.open(io.BytesIO(mp4)) as container:
        pictures = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
    assert len(pictures) == 121 and pictures[0].shape == (270, 480, 3)  # frame 0 and 120 frames
    orange = [((p[..., 0].astype(int) - p[..., 2] > 60) & (p[..., 0] > 120)).sum() for p in pictures]
    assert min(orange) > 100  # the sphere is in every frame

    assert any("image/png" in o.get("data", {}) for o in outputs)  # the energy plot
    energies = re.search(r"total energy (-?[\d.]+) J at t = 0, (-?[\d.]+) J at t = 1.92 s", text)
    assert energies, text
    start, end = (float(v) for v in energies.groups())
    # At t = 0: ½ M v² − M g·x (42 particles of 1 kg, 0.3 m up) plus the spin's ½ I ω², which lies
    # between 0 and ½ M R² ω² (every particle within R = 0.3 m of the centre).
    mass, lin, lift, spin_max = 42.0, 0.5 * 42.0 * (2.0 ** 2 + 1.0 ** 2), 42.0 * 9.8 * 0.3, 0.5 * 42.0 * 0.09 * 16.0
    assert lin + lift - 1e-3 < start < lin + lift + spin_max
    assert end < start  # the floor's damping takes energy
    assert "(11, 180, 320, 3) uint8" in text


FIT_NOTEBOOK = ROOT / "report" / "fit.ipynb"


def test_the_fit_notebook_aims_a_spinning_throw_at_a_target_and_recovers_e_and_mu_from_an_npz():
    outputs, text = executed(FIT_NOTEBOOK)

    # The aimed throw comes down over the target (the notebook prints the engine's landing point).
    aim = re.search(r"lands at \((-?[\d.]+), (-?[\d.]+)\), target \((-?[\d.]+), (-?[\d.]+)\): miss ([\d.]+) mm "
                    r"after (\d+) evaluations \(first guess missed by (\d+) mm\)", text)
    assert aim, text
    x, z, tx, tz, miss, evaluations, first_miss = (float(v) for v in aim.groups())
    assert np.hypot(x - tx, z - tz) < 1e-3 and miss < 1.0  # within a millimetre
    assert first_miss > 100 and evaluations <= 30  # the guess was well off; the gradient got there
    spin = re.search(r"spin = \((-?[\d.]+), (-?[\d.]+), (-?[\d.]+)\)", text)
    assert spin and any(abs(float(w) - s) > 0.01 for w, s in zip(spin.groups(), (0.0, 0.0, 2.0)))  # spin moved too

    # e and μ recovered from the NPZ recording (1 mm noise on x).
    fit = re.search(r"fitted e = ([\d.]+) \(recorded with 0.55\), mu = ([\d.]+) \(0.4\); loss ([\d.e+-]+) -> "
                    r"([\d.e+-]+) in (\d+) evaluations", text)
    assert fit, text
    e, mu, loss0, loss1, _n = (float(v) for v in fit.groups())
    assert e == pytest.approx(0.55, rel=0.02) and mu == pytest.approx(0.4, rel=0.05)
    assert loss1 < 1e-2 * loss0
    assert sum("image/png" in o.get("data", {}) for o in outputs) == 2  # the aim's and the fit's plots
