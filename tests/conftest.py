"""Shared fixtures: one Taichi runtime per test process (CPU, float32).

``ti.init`` resets every field and kernel, so the suite initialises once per
process; tests that need float64 or another arch run a subprocess.
The engine's kernels compile once per process (a few seconds, then Taichi's disk
cache), and a Simulator of any scene then builds in well under a second, so tests
build their own (``sim_cache``).

The suite runs on pytest-xdist workers (``-n auto`` in pyproject.toml, one per
CPU; ``-n 0`` runs it in one process). ``pytest_collection_modifyitems`` keeps
each test file on one worker and groups the files that share a float64 worker
process (GROUPS), heaviest first (ORDER). Most of the suite's CPU time is Taichi
compiling kernels in the grading, CLI and report processes the tests start (a
student's file compiles its own), so two workers on two cores take about half the
time of one process.

Taichi writes its disk cache of kernels when a process exits, under a lock; two
processes exiting at once (two workers, or a worker and a CLI run) may print
"Lock ... ticache.lock failed": the second one skips writing and the kernels it
compiled are compiled again by the next process that needs them. Harmless: the
cache holds machine code keyed by the kernels' source, never results.
"""
import contextlib
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

# Every Taichi process of the suite (workers, and the command lines, reports and notebooks they
# start, which inherit this) compiles with Taichi's advanced IR optimisations off
# (rigid.runtime.init_taichi's quick_compile): kernels compile faster and run slower, and the
# suite compiles far more than it simulates, so the whole suite takes less time this way
# (report/bench_versions.md, "The suite's time"). What it tests is the same code;
# results differ from the default's by round-off. test_many_bodies' pinned run uses the
# default, as users do. RIGID_QUICK_COMPILE=0 runs the whole suite with the default.
os.environ.setdefault("RIGID_QUICK_COMPILE", "1")

ROOT = Path(__file__).resolve().parent.parent
ASSETS = ROOT / "assets"
SOLUTION = ROOT / "rigid_body_dynamic.py"

# Files that must run in one worker process: they share a float64 worker (physics_results.py).
# The in-process runs of the engine go together, in one worker: Taichi writes its disk cache only
# when a process exits, so two workers running the same scenes, piles or contact laws would each
# compile the same kernels (a pile's set costs ~3 CPU-s), and the bit checks of the many-body speed
# paths build the same small piles (serial, parallel, parts, refresh, chunks); the CPU's references
# of the Vulkan and GPU-pipeline tests are runs of the same scenes.
GROUPS = {
    **dict.fromkeys(("test_physics_accuracy", "test_physics_energy", "test_physics_inertia",
                     "test_physics_momentum", "test_physics_rotation"), "physics_fp64"),
    **dict.fromkeys(("test_scenes", "test_many_bodies", "test_export_animation", "test_camera",
                     "test_multi_mesh_bodies", "test_report", "test_bench_many",
                     "test_core", "test_impulse", "test_panel", "test_window_grab", "test_window_shadow",
                     "test_skin", "test_neighbours", "test_refresh", "test_list_growth", "test_pair_parts",
                     "test_frame_chunks", "test_parallel_path",
                     "test_contact_materials", "test_sleep_materials", "test_pair_friction", "test_angle_of_repose",
                     "test_mesh_contact", "test_static_faces", "test_forces", "test_worlds", "test_sleep",
                     "test_backends", "test_gpu_pipeline"), "engine"),
}
# Groups by measured CPU time, longest first: xdist hands them out in collection order, each
# worker holding about two tests ahead, so the long ones start first and both workers end on
# short ones. The in-process "engine" group runs on one worker while the other takes the
# subprocess-bound files (the grading batch, the float64 gradients, Vulkan, sweeps); the rest
# follow in file order.
ORDER = ("engine", "test_grading_batch", "test_gradients", "test_sweep", "physics_fp64",
         "test_notebook", "test_view_memory", "test_export", "test_view_raster",
         "test_render", "test_window", "test_grading_handout")


def pytest_configure(config):
    # pytest-xdist 3.8 hands out the groups with the most tests first unless told not to: keep ORDER.
    if getattr(config.option, "loadscopereorder", None) is not None:
        config.option.loadscopereorder = False


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_auto_num_workers(config):
    """-n auto: one worker per CPU this process may use, at most 4 (each worker compiles its own
    copy of the simulators its tests share); none when the arguments name a single test file."""
    if os.environ.get("PYTEST_XDIST_AUTO_NUM_WORKERS"):
        return int(os.environ["PYTEST_XDIST_AUTO_NUM_WORKERS"])
    files = {str(arg).split("::")[0] for arg in config.args}
    if len(files) == 1 and next(iter(files)).endswith(".py"):
        return 0
    return min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)


@pytest.hookimpl(tryfirst=True)  # before xdist reads the groups
def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.get_closest_marker("xdist_group") is None:
            module = Path(str(item.fspath)).stem
            item.add_marker(pytest.mark.xdist_group(GROUPS.get(module, module)))
    if "PYTEST_XDIST_WORKER" not in os.environ:
        return  # one process: file order, which puts float32 tests beside the float64 workers
    rank = {name: i for i, name in enumerate(ORDER)}

    def group(item):
        mark = item.get_closest_marker("xdist_group")
        return mark.args[0] if mark.args else mark.kwargs.get("name", "default")

    items.sort(key=lambda item: rank.get(group(item), len(ORDER)))  # stable: file order otherwise


def pytest_collection_finish(session):
    """pytest-xdist schedules --dist loadgroup by a "@group" suffix it writes into each node id;
    pytest 9.2 keeps node ids elsewhere, so the suffix is lost and every file's tests spread over
    the workers (each one running the grading batch's fixture: the suite took twice as long).
    pyproject.toml pins pytest < 9; this says so loudly should another version break it again."""
    items = session.items
    if getattr(session.config.option, "loadgroup", False) and items and not all("@" in item.nodeid for item in items):
        message = (f"error: pytest-xdist's --dist loadgroup does not group tests with this pytest "
                   f"({pytest.__version__}); install the dev extra's pytest: pip install 'pytest<9'")
        print(message, file=sys.stderr)  # a worker's error reaches the terminal as xdist's own traceback
        raise pytest.UsageError(message)


@pytest.fixture(scope="session")
def ti_cpu():
    from rigid.runtime import init_taichi

    init_taichi("cpu", fp64=False)


@pytest.fixture(scope="session")
def units(ti_cpu):
    """The solution's units: the same module as rigid.Simulator's and the command line's default
    (rigid.engine.units.default_units), so that in-process runs of either share the kernels,
    which are compiled per units module (a second module would trace every kernel again)."""
    from rigid.engine.units import default_units

    assert Path(default_units().__file__).resolve() == SOLUTION.resolve()
    return default_units()


@pytest.fixture(scope="session")
def sim_cache(units):
    """sim_cache(**config) -> a new Simulator for that config (float32, the solution's units).
    Building one is cheap: the kernels are compiled once per process (rigid.engine.kernels)."""
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    def get(**config):
        return Simulator(SimConfig(fp64=False, **config).validate(), units)

    return get


def default_sigint():
    """preexec_fn for a child the test stops with SIGINT: Ctrl-C's default action, even when
    pytest itself runs with SIGINT ignored (started in the background by a shell)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@contextlib.contextmanager
def killed_at_exit(proc):
    """Yield ``proc``; kill it if it still runs afterwards (a failed test leaves no endless run)."""
    try:
        yield proc
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def venv_with_our_dependencies(folder: Path, extra_paths=()) -> Path:
    """A new venv (no pip) whose Python finds this environment's packages (numpy, taichi, ...)
    through a path file, but not this checkout's ``rigid``: the editable install's finder lives in
    a .pth file of this environment's site-packages, and Python runs .pth files only in its own
    site folders. ``extra_paths`` go first (e.g. an unpacked wheel). Returns its python."""
    import site
    import sysconfig

    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(folder)], check=True, timeout=120)
    python = folder / "bin" / "python"
    purelib = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             capture_output=True, text=True, check=True, timeout=60).stdout.strip()
    ours = [p for p in dict.fromkeys([*site.getsitepackages(), sysconfig.get_paths()["purelib"]])
            if Path(p).is_dir()]
    (Path(purelib) / "_our_dependencies.pth").write_text("\n".join([*map(str, extra_paths), *ours]) + "\n")
    return python


def run_cli(*args, timeout=120, cwd=ROOT, env=None):
    """Run ``python rigid_body_dynamic.py ARGS`` and return the CompletedProcess."""
    return subprocess.run([sys.executable, str(SOLUTION), *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=timeout, env=env)


def run_main(capsys, monkeypatch, *args):
    """The command line in this process: ``rigid.cli.main(ARGS)`` from the repository root, as
    rigid_body_dynamic.py calls it (with the solution's units), on the worker's Taichi runtime
    and compiled kernels; a process of its own costs ~2-3 s of CPU to start Taichi and build
    them. For what a run writes and prints; exit codes, signals and tracebacks of a real process
    are tested with run_cli. Returns (exit code, stdout, stderr)."""
    from rigid.cli import main

    monkeypatch.chdir(ROOT)
    capsys.readouterr()
    try:
        code = main([str(a) for a in args])
    except SystemExit as stop:  # argparse's own errors exit from inside main
        code = stop.code
    out, err = capsys.readouterr()
    return code, out, err
