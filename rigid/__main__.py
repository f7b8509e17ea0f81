"""``python -m rigid``: the simulator with the repository's rigid_body_dynamic.py units."""
from .cli import main

raise SystemExit(main())
