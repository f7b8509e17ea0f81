"""Kernel launches with their arguments set once, for the launches a run repeats.

A Taichi 1.7 kernel call from Python re-checks and re-sets every argument on every call:
~10 µs per ndarray, and the engine's kernels take ~50 (their argument packs), so a call
costs ~0.5 ms before the kernel starts. The parallel schedule launches once per substep,
so that was ~8 ms of host work per frame. ``PreparedLaunch`` does what Taichi's
``Kernel.launch_kernel`` does once (compile or load the kernel, build its launch context,
set the packs' ndarrays) and then only launches: the arrays are the Simulator's own and
live as long as it, and their contents, not their addresses, change between launches.

It relies on Taichi 1.7's Python internals (the project pins taichi < 1.8); where they are
not as expected it falls back to the plain call, which gives the same results.
"""
from __future__ import annotations


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


def _prepare(kernel, args):
    from taichi.lang import impl
    from taichi.lang._ndarray import Ndarray
    from taichi.lang.argpack import ArgPack

    primal = kernel._primal
    key = primal.ensure_compiled(*args)
    t_kernel = primal.compiled_kernels[key]
    packs, arrays, ints, later = [], [], {}, []
    for i, (value, argument) in enumerate(zip(args, primal.arguments)):
        if isinstance(value, ArgPack):  # its ndarrays go after the kernel's own arguments
            for name in argument.annotation.members:
                member = value[name]
                if not isinstance(member, Ndarray) or member.grad is not None:
                    raise TypeError("only packs of ndarrays are prepared")
                later.append(member.arr)
            packs.append(((i,), value._ArgPack__argpack))
        elif isinstance(value, Ndarray) and value.grad is None:
            arrays.append(((i,), value.arr))
        elif isinstance(value, int) and not isinstance(value, bool):
            ints[argument.name] = [(i,), value]
        else:
            raise TypeError(f"argument {argument.name}: not prepared")
    later = [((len(args) + j,), array) for j, array in enumerate(later)]
    program = impl.get_runtime().prog

    def launch(scalars):
        # A fresh context per launch: the launcher rewrites a context's array slots in place.
        # Setting ~50 slots here costs ~20 µs; Taichi's checks around it cost ~0.5 ms.
        context = t_kernel.make_launch_context()
        for name, value in scalars.items():
            ints[name][1] = int(value)
        for index, value in ints.values():
            context.set_arg_int(index, value)
        for index, array in arrays:
            context.set_arg_ndarray(index, array)
        for index, pack in packs:  # as Taichi orders it: the packs, then their arrays
            context.set_arg_argpack(index, pack)
        for index, array in later:
            context.set_arg_ndarray(index, array)
        program.launch_kernel(program.compile_kernel(program.config(), program.get_device_caps(), t_kernel), context)

    return launch
