"""MkDocs hook: a line ``<!-- report: NAME -->`` in a page becomes the tables of report/NAME.json,
made now by the same functions that write report/NAME.md, so the pages never hold typed figures;
the report's figures (report/figures/*.png, which those tables link to) join the site as figures/.

The benchmarks and the validation script write the JSON (python scripts/bench*.py, validate.py,
validate_materials.py); a page is as current as the JSON in the checkout.
"""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MARKER = re.compile(r"^<!-- report: (\w+) -->$", re.M)


def _generators():
    if str(ROOT) not in sys.path:  # the checkout's package, whether or not it is installed
        sys.path.insert(0, str(ROOT))
    from rigid.bench import contact, first_run, many_markdown, sweeps, table
    from rigid.science import materials, validation

    return {"bench": table.markdown, "bench_many": many_markdown.markdown, "validation": validation.markdown,
            "materials": materials.markdown, "bench_build": _build, "bench_record": _record,
            "bench_window": _window, "bench_sweep": sweeps.markdown, "contact": contact.report_markdown,
            "bench_first_run": first_run.markdown}


def on_files(files, config):
    from mkdocs.structure.files import File

    for png in sorted((ROOT / "report" / "figures").glob("*.png")):
        files.append(File.generated(config, f"figures/{png.name}", abs_src_path=str(png)))
    return files


def on_page_markdown(markdown: str, page, config, files) -> str:
    if "<!-- report:" not in markdown:
        return markdown
    generators = _generators()

    def expand(match: re.Match) -> str:
        name = match.group(1)
        if name not in generators:
            raise ValueError(f"{page.file.src_path}: no report table named {name!r}; known: {sorted(generators)}")
        data = json.loads((ROOT / "report" / f"{name}.json").read_text())
        return _nested(generators[name](data))

    return MARKER.sub(expand, markdown)


def _nested(text: str) -> str:
    """A report's markdown under a page's section: its title dropped, its headings two levels down."""
    lines = [line for line in text.splitlines() if not line.startswith("# ")]
    return "\n".join("##" + line if line.startswith("#") else line for line in lines).strip() + "\n"


def _table(header: list[str], rows: list[list]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(out) + "\n"


def _build(d: dict) -> str:
    """report/bench_build.json: building a Simulator and running its first frame."""
    return _table(["scene", "build, s", "first frame, s", "total, s"],
                  [[r["scene"], r["build_s"], r["first_frame_s"], r["total_s"]] for r in d["rows"]])


def _record(d: dict) -> str:
    """report/bench_record.json: where a recording's time goes."""
    rows = [[part, d[part]["seconds"], d[part]["ms_per_frame"], d[part]["fps"]]
            for part in ("simulate", "render", "encode", "record", "cli") if part in d]
    head = (f"{d['frames']} frames of `{d['scene']}` at {d['resolution'][0]}×{d['resolution'][1]} "
            f"({d['particles']:,} particles, {d['faces']:,} triangles), {d['mp4_bytes']:,} bytes of MP4.\n\n")
    return head + _table(["part", "seconds", "ms a frame", "frames/s"], rows)


def _window(d: dict) -> str:
    """report/bench_window.json: the window's frame, part by part (medians)."""
    rows = [[name, s["bodies"], f"{s['particles']:,}", s["median_ms"]["simulate"], s["median_ms"]["draw"],
             s["median_ms"]["panel"], s["median_ms"]["show"], s["fps"]] for name, s in d["scenes"].items()]
    head = f"{d['resolution'][0]}×{d['resolution'][1]}, medians of {d['frames']} frames.\n\n"
    return head + _table(["scene", "bodies", "particles", "simulate ms", "draw ms", "panel ms", "show ms",
                          "frames/s"], rows)
