"""What the TA reads: the points split, a table, the feedback; JSON and CSV for the gradebook.

JSON (DESIGN's contract): a list with one object per submission: "submission",
"total", "max_total", "todos": {"1": {"passed", "points", "max", "message"},
... "7"}, plus "seconds", "student" {"uid", "name"}, "output" (the
submission's captured output, truncated), "format" ("project" or "original")
and "notes" (what the TA should know, e.g. a mesh the submission lacks). CSV:
one row per submission: submission, uid, name, todo1..todo7, total,
max_total, feedback (the messages of the TODOs that lost points, then the
notes, each "note: ...").
"""
import csv
import json

from ..run.atomic import atomic_output
from .specs import TODOS


def points_line(points: dict) -> str:
    parts = ", ".join(f"{k} {TODOS[k].title} {points[k]:g}" for k in TODOS)
    return f"points per TODO: {parts} (total {sum(points.values()):g})"


def feedback(result: dict) -> list:
    return [t["message"] for t in result["todos"].values() if not t["passed"]]


def notes(result: dict) -> list:
    return [f"note: {n}" for n in result.get("notes", [])]


def table(results: list) -> str:
    width = max([len("submission")] + [len(r["submission"]) for r in results])
    head = f"{'submission':<{width}}  " + " ".join(f"{'T' + str(k):>4}" for k in TODOS) + "   total     time"
    rows = [head, "-" * len(head)]
    for r in results:
        cells = " ".join(f"{r['todos'][str(k)]['points']:>4g}" for k in TODOS)
        rows.append(f"{r['submission']:<{width}}  {cells}  {r['total']:>3g}/{r['max_total']:<3g}"
                    f" {r['seconds']:>6.1f} s")
    return "\n".join(rows)


def details(results: list) -> str:
    """The messages of lost TODOs and the notes per submission; one line when every TODO lost for the
    same reason."""
    lines = []
    for r in results:
        lost = feedback(r)
        if not lost and not notes(r):
            continue
        lines.append(f"{r['submission']}:" + (" (original handout format)" if r.get("format") == "original" else ""))
        reasons = {m.split(": ", 1)[-1] for m in lost}
        if len(lost) == len(TODOS) and len(reasons) == 1:
            lines.append(f"  TODOs 1-{len(TODOS)}: {reasons.pop()}")
        else:
            lines.extend(f"  {m}" for m in lost)
        lines.extend(f"  {n}" for n in notes(r))
    return "\n".join(lines)


def write_json(results: list, path) -> None:
    with atomic_output(path) as tmp:
        tmp.write_text(json.dumps(results, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")


def write_csv(results: list, path) -> None:
    with atomic_output(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["submission", "uid", "name", *(f"todo{k}" for k in TODOS), "total", "max_total", "feedback"])
        for r in results:
            student = r.get("student", {})
            w.writerow([r["submission"], student.get("uid", ""), student.get("name", ""),
                        *(f"{r['todos'][str(k)]['points']:g}" for k in TODOS), f"{r['total']:g}",
                        f"{r['max_total']:g}", " | ".join(feedback(r) + notes(r))])
