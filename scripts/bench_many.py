"""Many-body speed (MuJoCo pile, cost against particle count, 1,000 bodies) -> report/bench_many.* (logic: rigid.bench.many)."""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.bench.many import run  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="a smoke run: small sizes, seconds")
    ap.add_argument("--out", type=Path, default=ROOT / "report", help="folder for bench_many.json/.md and figures/")
    args = ap.parse_args(argv)
    run(args.out, quick=args.quick)
    print(f"wrote {args.out / 'bench_many.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
