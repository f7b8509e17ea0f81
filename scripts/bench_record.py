"""Benchmark --record: simulation, rendering and encoding (the logic lives in rigid.bench.recording)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.bench.recording import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
