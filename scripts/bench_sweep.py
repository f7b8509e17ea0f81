"""Benchmark sweeps: 64 runs of the thrown sphere against single command-line runs, and Ray's local
cluster against the local pool (the logic lives in rigid.bench.sweeps; writes report/bench_sweep.json).

    python scripts/bench_sweep.py                  # 64 runs of 60 frames, medians of 3
    python scripts/bench_sweep.py --runs 16 --repeats 1 --no-ray --out /tmp/b.json
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.bench.sweeps import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
