"""Benchmark the window: simulating vs drawing a frame (the logic lives in rigid.bench.window)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.bench.window import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
