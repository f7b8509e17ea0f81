"""Resting heights, closest approach, a 6-box stack's jitter and penetration and a box on a 30° ramp
beside PyBullet's hull of the same mesh -> report/contact.md
and report/contact.json (logic: rigid.bench.contact; PyBullet from the optional ``peers`` extra)."""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", type=Path, default=ROOT / "report", help="folder for contact.md and contact.json")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON, write nothing (a column's run)")
    args = ap.parse_args(argv)
    import json

    import rigid
    from rigid.bench.contact import measure, write
    from rigid.bench.peers import versions
    from rigid.engine.units import default_units

    rigid.init("cpu")
    peers = versions()["pybullet"] is not None
    if not peers:
        print("note: PyBullet is not installed (pip install '.[peers]'): its column is left out", file=sys.stderr)
    rows = measure(default_units(), peers=peers)
    if args.json:
        print(json.dumps(rows))
        return 0
    write(args.out, rows)
    print(f"wrote {args.out / 'contact.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
