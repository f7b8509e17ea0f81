"""A sweep's output folder: ``sweep.json`` (what the sweep is), ``index.csv`` (a row per run),
``runs/<run>.npz`` and, with ``--record``, ``runs/<run>.mp4``.

Every file is written under a hidden temporary name and renamed when complete
(rigid.run.atomic), by the driver only, so an interrupted or killed sweep leaves complete files
and at most some hidden partial ones, which the next start removes. A run counts as finished
when index.csv says ``ok`` and its files are there: re-running the same command keeps those
and runs the rest again. A folder that holds another sweep (another scene, frame count or set
of runs) is refused rather than mixed.
"""
from __future__ import annotations

import csv
import hashlib
import io
import json
from pathlib import Path

from ..errors import UserError
from ..run.atomic import atomic_output, check_output_path

INDEX, MANIFEST, RUNS = "index.csv", "sweep.json", "runs"
NOT_RUN = "not run"


class SweepFolder:
    def __init__(self, out, runs, keys: list[str], scene_text: str, frames: int, record: bool):
        self.out, self.runs, self.keys, self.record = Path(out), runs, keys, record
        self.manifest = {
            "scene_sha256": hashlib.sha256(scene_text.encode()).hexdigest(),
            "frames": frames,
            "runs": {r.name: {**r.values, "seed": r.seed} for r in runs},
        }

    # --- opening ---------------------------------------------------------------------------------
    def check(self) -> dict:
        """Refuse a folder this sweep cannot use, writing nothing; return the rows of the runs
        finished before (name -> row)."""
        out, manifest = self.out, self.out / MANIFEST
        if out.exists() and not out.is_dir():
            raise UserError(f"--out {out} is a file; give a folder (new, or a sweep's to resume it)")
        if out.is_dir() and not manifest.is_file() and any(out.iterdir()):
            raise UserError(f"--out {out} holds other files and no {MANIFEST}: it is not a sweep's folder; "
                            f"pick a new or empty folder")
        if manifest.is_file():
            self._check_same_sweep(manifest)
        return self._finished_before()

    def prepare(self) -> None:
        """Make the folder ready to take files (after ``check``)."""
        out, manifest = self.out, self.out / MANIFEST
        try:
            (out / RUNS).mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise UserError(f"--out {out}: cannot make the folder ({err.strerror or type(err).__name__}); "
                            f"pick another path") from None
        check_output_path(out / INDEX)  # a folder that takes no files: one line now
        self.remove_partials()
        if not manifest.is_file():
            self._write_text(manifest, json.dumps(self.manifest, indent=1) + "\n")

    def _check_same_sweep(self, path: Path) -> None:
        try:
            before = json.loads(path.read_text())
        except (OSError, ValueError):
            raise UserError(f"--out {self.out}: {MANIFEST} is unreadable; pick a new folder") from None
        now = self.manifest
        for key, what in (("scene_sha256", "another scene file (or the file changed)"),
                          ("frames", f"{before.get('frames')} frames, not {now['frames']}"),
                          ("runs", "other --vary values or --seeds")):
            if before.get(key) != json.loads(json.dumps(now[key])):
                raise UserError(f"--out {self.out} holds another sweep ({what}); give the same command to "
                                f"resume it, or use another --out")

    def _finished_before(self) -> dict:
        index = self.out / INDEX
        if not index.is_file():
            return {}
        with open(index, newline="") as f:
            rows = {row.get("run"): row for row in csv.DictReader(f)}
        return {r.name: rows[r.name] for r in self.runs
                if r.name in rows and rows[r.name].get("status") == "ok" and self._files_there(r.name)}

    def _files_there(self, name: str) -> bool:
        return self.npz(name).is_file() and (not self.record or self.mp4(name).is_file())

    def remove_partials(self) -> None:
        """The hidden partial files of writes that never finished (a killed driver)."""
        for folder in (self.out, self.out / RUNS):
            for path in folder.glob(".*.partial*"):
                path.unlink(missing_ok=True)

    # --- writing ---------------------------------------------------------------------------------
    def npz(self, name: str) -> Path:
        return self.out / RUNS / f"{name}.npz"

    def mp4(self, name: str) -> Path:
        return self.out / RUNS / f"{name}.mp4"

    def write_run(self, name: str, npz: bytes, mp4: bytes | None) -> None:
        self._write_bytes(self.npz(name), npz)
        if mp4 is not None:
            self._write_bytes(self.mp4(name), mp4)

    def row(self, run, status: str = NOT_RUN, energy=None, seconds=None) -> dict:
        return {"run": run.name, **{k: run.values[k] for k in self.keys}, "seed": run.seed, "status": status,
                "final_energy": "" if energy is None else repr(float(energy)),
                "wall_seconds": "" if seconds is None else f"{float(seconds):.3f}"}

    def write_index(self, rows: dict) -> None:
        """One row per run of the sweep, in run order (``rows``: name -> row; others "not run")."""
        text = io.StringIO()
        writer = csv.DictWriter(text, ["run", *self.keys, "seed", "status", "final_energy", "wall_seconds"],
                                lineterminator="\n")
        writer.writeheader()
        for run in self.runs:
            writer.writerow(rows.get(run.name) or self.row(run))
        self._write_text(self.out / INDEX, text.getvalue())

    def _write_text(self, path: Path, text: str) -> None:
        self._write_bytes(path, text.encode())

    @staticmethod
    def _write_bytes(path: Path, data: bytes) -> None:
        with atomic_output(path) as tmp:
            tmp.write_bytes(data)
