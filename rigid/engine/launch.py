"""Kernel launches with their arguments set once, for the launches a run repeats.

A Taichi 1.7 kernel call from Python re-checks and re-sets every argument on every call:
~10 µs per ndarray, and the engine's kernels take ~50 (their argument packs), so a call
costs ~0.5 ms before the kernel starts. The parallel schedule launches once per substep,
so that was ~8 ms of host work per frame. ``PreparedLaunch`` does what Taichi's
``Kernel.launch_kernel`` does once (compile or load the kernel, build its launch context,
set the packs' ndarrays) and then only launches: the arrays are the Simulator's own and
live as long as it, and their contents, not their addresses, change between launches.

On the CPU it goes one step further: each ndarray is given to the launch context once, as
the raw address of its memory (Taichi's way for numpy arrays), so one context serves every
launch. An ndarray given as such is a device handle, which Taichi's CPU launcher replaces
in the context by the address at each launch, so a context of ndarrays had to be rebuilt
and its ~57 arrays set again each time: ~50 µs a launch, 90 µs a frame with the launch
itself, against 5 µs of simulation for a lone sphere stepped frame by frame.

It relies on Taichi 1.7's Python internals (the project pins taichi < 1.8); where they are
not as expected it falls back to the plain call, which gives the same results.
"""
from __future__ import annotations

from ..runtime import compile_settings
from . import broadphase
from .arrays import _cpu_pointer, byte_size
from .broadphase_host import cell
from .refresh import PENDING
from .threads import pin_workers


class PreparedLaunch:
    def __init__(self, kernel, *args):
        """``kernel(*args)`` made ready; ``args`` are argument packs, ndarrays, ints and floats."""
        self._kernel, self._args = kernel, list(args)
        try:
            self._launch = _prepare(kernel, self._args)
        except Exception:  # other Taichi internals: the plain call
            self._launch = None

    def __call__(self, **scalars) -> None:
        """Launch; ``scalars`` give new values to int arguments, by their names in the kernel."""
        if self._launch is None:
            names = [a.name for a in self._kernel._primal.arguments]
            for name, value in scalars.items():
                self._args[names.index(name)] = value
            self._kernel(*self._args)
            return
        self._launch(scalars)

    @property
    def prepared(self) -> bool:
        return self._launch is not None


def schedule_launches(schedule: str, kernels, model, state, world, scratch, rows) -> dict:
    """The launches a run repeats on ``schedule``: "serial", a chunk of frames in one launch
    (``run_frames``); "parallel", a substep (``substep``, or on a CPU its parts:
    split_substep.py) and a frame's end (``finish_frame``)."""
    if schedule == "serial":
        return dict(run_frames=PreparedLaunch(kernels.run_frames, model, state, world, scratch, rows, 1, 1))
    pin_workers()  # one CPU worker to a core (threads.py), or a parallel loop often runs on one
    rebuild = cell(scratch, broadphase.REBUILD)  # neighbours.rebuild_gate
    if kernels.split is not None and rebuild.on_cpu:  # the substep in parts: split_substep.py
        substep = SplitLaunch(kernels.split, rebuild, model, state, world, scratch)
    else:
        substep = PreparedLaunch(kernels.substep, model, state, world, scratch)
    return dict(substep=substep, finish_frame=PreparedLaunch(kernels.finish_frame, model, state, world, scratch, rows, 0))


class SplitLaunch:
    """A parallel substep as split_substep.py's parts: the motion test, then a refresh's search if
    it left one pending, then the placement and rebuild or the placement alone, as the rebuild flag
    (``rebuild``, an IntCell) says, then the forces and the update."""

    def __init__(self, split, rebuild, model, state, world, scratch):
        self._rebuild = rebuild
        self._motion = PreparedLaunch(split.motion, model, state, scratch)
        self._refresh = PreparedLaunch(split.refresh, model, state, scratch) if split.refresh else None
        self._build = PreparedLaunch(split.build, model, state, scratch)
        self._place = PreparedLaunch(split.place, model, state, scratch)
        self._forces = PreparedLaunch(split.forces, model, state, world, scratch)

    def __call__(self) -> None:
        self._motion()
        if self._refresh is not None and self._rebuild.value == PENDING:
            self._refresh()
        (self._build if self._rebuild.value else self._place)()
        self._forces()

    @property
    def prepared(self) -> bool:
        launches = (self._motion, self._refresh, self._build, self._place, self._forces)
        return all(p.prepared for p in launches if p is not None)


def run_chunk(launches: dict, schedule: str, frames: int, substeps: int) -> None:
    """``frames`` frames of ``substeps`` substeps (rows 0 .. frames − 1) through ``launches``."""
    if schedule == "serial":
        launches["run_frames"](frames=frames, substeps=substeps)
        return
    for frame in range(frames):
        for _ in range(substeps):
            launches["substep"]()
        launches["finish_frame"](slot=frame)


def _prepare(kernel, args):
    from taichi.lang import impl
    from taichi.lang._ndarray import Ndarray
    from taichi.lang.argpack import ArgPack

    primal = kernel._primal
    key = primal.ensure_compiled(*args)
    t_kernel = primal.compiled_kernels[key]
    packs, arrays, ints, members = [], [], {}, []
    for i, (value, argument) in enumerate(zip(args, primal.arguments)):
        if isinstance(value, ArgPack):  # its ndarrays go after the kernel's own arguments
            for name in argument.annotation.members:
                member = value[name]
                if not isinstance(member, Ndarray) or member.grad is not None:
                    raise TypeError("only packs of ndarrays are prepared")
                members.append(member)
            packs.append(((i,), value._ArgPack__argpack))
        elif isinstance(value, Ndarray) and value.grad is None:
            arrays.append(((i,), value))
        elif isinstance(value, int) and not isinstance(value, bool):
            ints[argument.name] = [(i,), value]
        else:
            raise TypeError(f"argument {argument.name}: not prepared")
    # As Taichi orders them: the kernel's own arguments, the packs, then the packs' arrays.
    later = [((len(args) + j,), array) for j, array in enumerate(members)]
    program = impl.get_runtime().prog
    addresses = [_cpu_pointer(array) for _index, array in arrays + later]

    settings = getattr(kernel, "settings", {})  # rigid.runtime.SettingsKernel's, else the process's
    held = []  # Taichi's own cache holds it for the program's life: looked up once, as compiled

    def compiled():
        if not held:
            with compile_settings(**settings):
                held.append(program.compile_kernel(program.config(), program.get_device_caps(), t_kernel))
        return held[0]

    def set_ints(context, scalars):
        for name, value in scalars.items():
            ints[name][1] = int(value)
        for index, value in ints.values():
            context.set_arg_int(index, value)

    if all(address is not None for address in addresses):  # the CPU: one context for every launch
        context = t_kernel.make_launch_context()
        for (index, array), address in zip(arrays + later, addresses):
            context.set_arg_external_array_with_shape(index, address, byte_size(array), list(array.shape), 0)
        for index, pack in packs:
            context.set_arg_argpack(index, pack)

        def launch(scalars):
            set_ints(context, scalars)
            program.launch_kernel(compiled(), context)

        return launch

    def launch_fresh(scalars):
        # A fresh context per launch: the launcher rewrites a context's array slots in place.
        context = t_kernel.make_launch_context()
        set_ints(context, scalars)
        for index, array in arrays:
            context.set_arg_ndarray(index, array.arr)
        for index, pack in packs:
            context.set_arg_argpack(index, pack)
        for index, array in later:
            context.set_arg_ndarray(index, array.arr)
        program.launch_kernel(compiled(), context)

    return launch_fresh
