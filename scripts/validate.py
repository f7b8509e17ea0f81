"""Check the physics against outside references -> report/validation.md (the logic lives in rigid.science.validation)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.science.validation import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
