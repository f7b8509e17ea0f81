"""``python -m rigid sweep SCENE.toml --vary KEY=START:STOP:N ... --frames F --out DIR``.

Exit codes: 0 every run ok; 1 some runs failed (their lines are in index.csv; the same command
retries them); 2 bad input, one line, before anything runs; 130 Ctrl-C (finished runs kept).
"""
from __future__ import annotations

import argparse
import sys

from ..errors import UserError

EPILOG = """examples:
  python -m rigid sweep assets/scenes/thrown_sphere.toml --vary restitution=0.2:0.8:4 \\
      --vary friction=0.1,0.5 --frames 120 --out sweeps/bounce
  python -m rigid sweep assets/scenes/pile.toml --vary count=4,8 --seeds 3 --frames 60 --out sweeps/pile --record
  python -m rigid sweep assets/scenes/thrown_sphere.toml --vary initial_velocity.x=1:4:4 --frames 60 \\
      --out sweeps/throw --ray local
re-running the same command resumes: finished runs are kept, failed ones run again.
"""


class _OneLineParser(argparse.ArgumentParser):
    """argparse, but a bad flag gives one line (not the whole usage) and exit code 2."""

    def error(self, message):
        self.exit(2, f"error: {message}; see {self.prog} --help\n")


def build_parser() -> argparse.ArgumentParser:
    p = _OneLineParser(prog="python -m rigid sweep", epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       description="Many runs of one scene: the product of the --vary values (x seeds), "
                                   "each run's trajectory an NPZ, a row per run in DIR/index.csv.")
    p.add_argument("scene", metavar="SCENE.toml", help="the scene file every run starts from")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=START:STOP:N|KEY=a,b,c",
                   help="a scene key and its values: a range (N values, both ends included) or a list; "
                        "a vector's component as KEY.x, e.g. initial_velocity.x=1:4:4; give it once per key")
    p.add_argument("--seeds", type=int, default=1, metavar="N",
                   help="run each combination with N seeds: the scene's seed, +1, ... (default 1)")
    p.add_argument("--frames", type=int, required=True, metavar="F", help="frames every run simulates")
    p.add_argument("--out", required=True, metavar="DIR", help="the sweep's folder (new, or a sweep's to resume)")
    p.add_argument("--workers", type=int, metavar="N", help="worker processes (default: one per CPU)")
    p.add_argument("--ray", metavar="ADDRESS|local",
                   help="run on a Ray cluster (the cluster extra): an address, or local to start one here")
    p.add_argument("--record", action="store_true", help="also render each run into DIR/runs/<run>.mp4")
    return p


def main(argv=None, units=None) -> int:
    """``units``: the module whose TODO units the runs use (rigid_body_dynamic.py passes itself)."""
    args = build_parser().parse_args(argv)
    from .driver import sweep

    try:
        rows = sweep(args.scene, args.vary, frames=args.frames, out=args.out, seeds=args.seeds,
                     workers=args.workers, ray=args.ray, record=args.record, units=units)
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return err.exit_code
    except KeyboardInterrupt:
        print(f"interrupted: the finished runs are kept in {args.out}; run the same command again to go on",
              file=sys.stderr)
        return 130
    return 0 if all(row["status"] == "ok" for row in rows) else 1
