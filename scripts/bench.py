"""Speed per substep (handout loop, engine, MuJoCo), start-up and memory -> report/bench.md (the logic lives in rigid.bench.speed)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.bench.speed import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
