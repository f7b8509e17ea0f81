"""scripts/validate.py's tracked outputs hold no run-to-run noise (issue 15, item 12): timings
go to an untracked file, numbers keep the digits that are stable. Checked on the formatting
function with two results that differ as two runs (or two machines) do, not by validating twice."""
import json

import numpy as np

from conftest import ROOT


def _noisy(value, rng, path=""):
    """The result as another run might give it: new timings, every number off in its last digits,
    float64 round-off (values below 1e-12) replaced by other round-off."""
    if isinstance(value, dict):
        return {k: (rng.uniform(0.01, 60.0) if k == "seconds" else _noisy(v, rng, f"{path}.{k}"))
                for k, v in value.items()}
    if isinstance(value, list):
        return [_noisy(v, rng, path) for v in value]
    if isinstance(value, float):
        if abs(value) < 1e-12:
            return float(rng.uniform(-9e-13, 9e-13))
        return value * (1 + rng.uniform(-1e-9, 1e-9))
    return value


def test_two_noisy_runs_give_identical_tracked_files():
    from rigid.science.validation import committed_outputs

    committed = json.loads((ROOT / "report" / "validation.json").read_text())
    rng = np.random.default_rng(0)
    first, second = _noisy(committed, rng), _noisy(committed, rng)
    first["seconds"], second["seconds"] = 41.7, 19.8
    a, b = committed_outputs(first), committed_outputs(second)
    assert a[0] == b[0] and a[1] == b[1]  # validation.json, validation.md
    assert a[2] != b[2] and "seconds" in a[2]  # the timings differ, in the untracked file
    assert '"seconds"' not in a[0] and "seconds" not in a[1]
    assert "< 1e-12" in a[1]  # round-off shown as a bound, not as digits


def test_committed_files_are_the_formatting_of_themselves():
    """report/validation.{json,md} as committed are what committed_outputs writes (a fixed point):
    they were written in this format, so a rerun changes them only where the physics changed."""
    from rigid.science.validation import committed_outputs

    committed = (ROOT / "report" / "validation.json").read_text()
    json_text, md_text, timings = committed_outputs(json.loads(committed))
    assert json_text == committed
    assert md_text == (ROOT / "report" / "validation.md").read_text()
    assert json.loads(timings) == {}


def test_timings_file_is_not_tracked():
    assert "report/validation_timings.json" in (ROOT / ".gitignore").read_text().splitlines()
