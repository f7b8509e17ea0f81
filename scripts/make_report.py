"""Regenerate report/report.md and report/report.pdf (the logic lives in rigid.report.build)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.report.build import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
