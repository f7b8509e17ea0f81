"""Many-body speed (PyBullet and MuJoCo side by side, sleeping, a small scene's fixed cost, stage profile,
MuJoCo pile, cost against particle count, 1,000 bodies) -> report/bench_many.* (logic: rigid.bench.many)."""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.bench.many import SECTIONS, run  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="a smoke run: small sizes, seconds")
    ap.add_argument("--out", type=Path, default=ROOT / "report", help="folder for bench_many.json/.md and figures/")
    ap.add_argument("--only", metavar="NAMES", help=f"comma-separated sections to run (of {','.join(SECTIONS)}); "
                    "the others are kept from the JSON already in --out")
    args = ap.parse_args(argv)
    sections = SECTIONS
    if args.only:
        sections = tuple(s.strip() for s in args.only.split(",") if s.strip())
        unknown = sorted(set(sections) - set(SECTIONS))
        if unknown:
            print(f"error: --only {','.join(unknown)}: no such section; use some of {','.join(SECTIONS)}", file=sys.stderr)
            return 2
    run(args.out, quick=args.quick, sections=sections)
    print(f"wrote {args.out / 'bench_many.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
