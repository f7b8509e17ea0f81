"""Measure the grader: preparation, per-submission and batch times (the logic lives in rigid.bench.grading)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.bench.grading import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
