"""Two checkouts' speed per substep, interleaved, and their ratio (the logic lives in rigid.bench.versions)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.bench.versions import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
