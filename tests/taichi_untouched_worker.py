"""Prints "same" if importing rigid, building a Simulator and running it leaves
every function, class and module that Taichi's modules (and their classes) hold as it was, else
what changed (Taichi's own counters and runtime objects change as it runs: those are not code).
In a process of its own: the suite's processes have imported rigid already."""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import types  # noqa: E402

import taichi  # noqa: E402,F401


def _code(value) -> bool:
    return callable(value) or isinstance(value, (types.ModuleType, staticmethod, classmethod, property))


def snapshot() -> dict:
    seen = {}
    for name, module in list(sys.modules.items()):
        if not (name == "taichi" or name.startswith("taichi.")) or module is None:
            continue
        for attr, value in list(vars(module).items()):
            if _code(value):
                seen[(name, attr)] = id(value)
            if isinstance(value, type) and value.__module__ == name:
                for member, inner in list(vars(value).items()):
                    if _code(inner):
                        seen[(name, f"{attr}.{member}")] = id(inner)
    return seen


def main():
    before = snapshot()
    import rigid

    rigid.init("cpu")
    sim = rigid.Simulator(rigid.load_scene(ROOT / "assets" / "scenes" / "thrown_sphere.toml"))
    sim.advance(2)
    after = snapshot()
    changed = sorted(f"{m}.{a}" for (m, a), i in before.items() if (m, a) in after and after[(m, a)] != i)
    print("same" if not changed else "changed: " + ", ".join(changed[:20]))


if __name__ == "__main__":
    main()
