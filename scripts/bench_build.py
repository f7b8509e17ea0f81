"""Build and first-frame time of successive Simulators in one process -> report/bench_build.* (logic: rigid.bench.build)."""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.bench.build import run  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeats", type=int, default=3, help="child processes (medians are reported)")
    ap.add_argument("--out", type=Path, default=ROOT / "report", help="folder for bench_build.json/.md")
    args = ap.parse_args(argv)
    result = run(args.out, args.repeats)
    for row in result["rows"]:
        print(f"{row['scene']:>26}: build {row['build_s']:.3f} s, first frame {row['first_frame_s']:.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
