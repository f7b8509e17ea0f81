"""Generate the project's meshes in assets/ with trimesh (the logic lives in rigid.bodies.assets)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rigid.bodies.assets import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
