"""The answers file shipped beside the handout, for ``python rigid_body_dynamic.py --check``.

``rigid_body_dynamic.check.npz`` holds the reference's answers exactly as the
grader computes them (expected.py: the outputs of each TODO on the seeded
inputs of specs.py, and the reference trajectory at its checkpoints): numbers
only, never code, so it gives nothing away that running the grader on your own
file would not. It is copied from the grader's prepared answers (batch.prepare),
so the self-check and grade.py compare with the same numbers. It also holds a
fingerprint of the inputs (the seeds, the samples, the trajectory scenario): an
answers file made for other inputs is refused with a one-line error instead of
failing every TODO.
"""
import hashlib
from pathlib import Path

import numpy as np

from ..errors import UserError
from .expected import Expected
from .specs import SAMPLES, SEED, TODOS, sample_inputs

FILE_NAME = "rigid_body_dynamic.check.npz"
FINGERPRINT = "meta/fingerprint"


def fingerprint() -> np.ndarray:
    """sha256 (32 uint8) of every input the answers depend on, each rounded to float32 first: the
    inputs are computed (random draws turned into rotations and inverses), and another version of
    a dependency may change their last float64 bit, which changes no answer (on this machine's fresh
    install the float64 fingerprint no longer matched the shipped file, while every answer in it
    still agreed to 1e-9)."""
    from . import trajectory

    h = hashlib.sha256(f"{SEED} {SAMPLES}".encode())
    for k in TODOS:
        for name, value in sorted(sample_inputs(k).items()):
            h.update(name.encode())
            h.update(_rounded(value))
    config, geometry = trajectory.scenario()
    h.update(_rounded(geometry.particles))
    numbers = [trajectory.SUBSTEPS_PER_CHECKPOINT, trajectory.CHECKPOINTS]
    for name in ("particle_mass", "dt", "gravity", "position", "initial_velocity", "initial_angular_velocity",
                 "collision_stiffness", "velocity_damping_stiffness", "friction_stiffness"):
        numbers += list(np.ravel(np.asarray(getattr(config, name, np.nan), np.float64)))
    h.update(_rounded(numbers))
    return np.frombuffer(h.digest(), np.uint8)


def _rounded(values) -> bytes:
    return np.ascontiguousarray(values, np.float64).astype(np.float32).tobytes()


def make(solution: Path, out, log=print) -> None:
    """Write the answers file ``out`` for ``solution``, from the grader's prepared answers (prepared now
    if this grader version has not been yet: the reference must also pass the grader's own checks)."""
    from ..run.atomic import atomic_output
    from .batch import default_cache_root, prepare
    from .sandbox import Limits

    settings = prepare(Path(solution).resolve(), Limits(), default_cache_root(), log=log)
    with atomic_output(out) as tmp:
        write(settings.expected, tmp)


def write(expected_npz: Path, out: Path) -> None:
    """The answers file from the grader's prepared expected.npz (written atomically by the caller)."""
    with np.load(expected_npz, allow_pickle=False) as data:
        values = {key: data[key] for key in data.files}
    if not all(np.issubdtype(v.dtype, np.number) for v in values.values()):
        raise UserError(f"{expected_npz} holds something other than numbers; refusing to ship it")
    values[FINGERPRINT] = fingerprint()
    with open(out, "wb") as f:
        np.savez(f, **values)


def load(path: Path) -> Expected:
    """The answers as an expected.Expected; UserError (one line for the student) if missing or stale."""
    if not path.is_file():
        raise UserError(f"no answers file {path.name} beside {path.parent / 'rigid_body_dynamic.py'}; it comes "
                        f"with the handout (a TA makes it with scripts/make_handout.py)")
    try:
        expected = Expected(path)
    except Exception as err:  # a truncated or foreign file
        raise UserError(f"{path.name} is not a readable answers file ({type(err).__name__}); get it again "
                        f"with the handout")
    stamp = expected.values.get(FINGERPRINT)
    if stamp is None or not np.array_equal(stamp, fingerprint()):
        raise UserError(f"{path.name} was made for other inputs than this version of the checks; get the "
                        f"answers file that came with your handout's version of rigid/")
    return expected
