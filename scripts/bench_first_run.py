"""Cold and warm first runs of every shipped scene -> report/bench_first_run.* (logic: rigid.bench.first_run)."""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.bench.first_run import run  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--tree", type=Path, action="append",
                    help="a source tree to measure (repeat to compare trees, interleaved; default: this one)")
    ap.add_argument("--scene", type=Path, action="append", help="only these scene files (default: all shipped)")
    ap.add_argument("--out", type=Path, default=ROOT / "report", help="folder for bench_first_run.json/.md")
    args = ap.parse_args(argv)
    run(args.out, [t.resolve() for t in (args.tree or [ROOT])], args.scene)
    return 0


if __name__ == "__main__":
    sys.exit(main())
