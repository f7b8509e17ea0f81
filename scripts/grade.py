"""Grade Assignment 3 submissions TODO by TODO (see rigid/grading/cli.py and README).

    python scripts/grade.py PATH... [--json OUT.json] [--csv OUT.csv] [--jobs N] [--points P1,...,P7]
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.grading.cli import main  # noqa: E402

if __name__ == "__main__":
    raise SystemExit(main())
