"""Measure restitution and friction against closed forms -> report/materials.json, materials.md
(the logic lives in rigid.science.materials)."""
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))


def main() -> int:
    from rigid.runtime import init_taichi
    from rigid.science.materials import markdown, measure

    init_taichi("cpu", fp64=False)
    out = Path(__file__).resolve().parent.parent / "report"
    m = measure()
    (out / "materials.json").write_text(json.dumps(m, indent=1) + "\n")
    (out / "materials.md").write_text(markdown(m))
    print(markdown(m))
    return 0


if __name__ == "__main__":
    sys.exit(main())
