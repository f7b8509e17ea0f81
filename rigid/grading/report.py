"""What the TA reads: the points split, a table, the feedback; JSON and CSV for the gradebook.

JSON (DESIGN's contract): a list with one object per submission: "submission",
"total", "max_total", "todos": {"1": {"passed", "points", "max", "message"},
... "7"}, plus "seconds", "student" {"uid", "name"}, "output" (the
submission's captured output, truncated), "format" ("project" or "original")
and "notes" (what the TA should know, e.g. a mesh the submission lacks). CSV:
one row per submission: submission, uid, name, todo1..todo7, total,
max_total, feedback (the messages of the TODOs that lost points, then the
notes, each "note: ...").

``summary(results)``: what a TA reads first about a batch: the score
histogram, the TODOs lost most often with their commonest messages, the
submissions that could not be graded at all and why, and how many carry notes.
grade.py prints it and writes it beside the CSV and JSON (``--summary``).
"""
import csv
import json
import re
from collections import Counter

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


def _ungradable(result: dict) -> str:
    """Why no TODO of a submission could be graded ('' when some could)."""
    messages = [t["message"] for t in result["todos"].values()]
    if not messages or not all("not graded" in m for m in messages):
        return ""
    reasons = Counter(m.split("not graded", 1)[1].lstrip(" —-(").rstrip(")") for m in messages)
    return reasons.most_common(1)[0][0]


def _shape(message: str) -> str:
    """A message with its numbers and line numbers blanked, so that the same mistake groups together."""
    return re.sub(r"(?<![\w⁻#'])(?<!TODO )\d+(\.\d+)?(e[-+]?\d+)?(?![\w⁻])", "#", message.split(": ", 1)[-1])


NOTE_KINDS = (("bonus terms", "bonus terms graded as 0"), ("edits of the given code", "edits of the given code"),
              ("the file reads", "a mesh the submission lacks"), ("the file calls ti.init", "ti.init called twice"),
              ("TODO comments missing", "TODOs found without their comment"), ("TODO", "a marker read twice"),
              ("the file runs no window loop", "no window loop"),
              ("the submission", "attempts outside its folder (files, network, programs)"))


def summary(results: list, top: int = 3) -> str:
    """The batch at a glance (plain text, for the terminal and a file)."""
    if not results:
        return "no submissions"
    n, max_total = len(results), max(r["max_total"] for r in results)
    totals = sorted(r["total"] for r in results)
    original = sum(r.get("format") == "original" for r in results)
    lines = [f"Batch summary: {n} submission{'s' if n > 1 else ''}"
             + (f" ({original} in the course's original handout format)" if original else "")
             + f"; mean {sum(totals) / n:.1f}/{max_total:g}, median {totals[n // 2]:g}", "", "Scores:"]
    width = max_total / 10 if max_total else 1
    bins = Counter(min(9, int(t // width)) if t < max_total else 10 for t in totals)
    for b in range(11):
        label = f"{max_total:g}" if b == 10 else f"[{b * width:g}, {(b + 1) * width:g})"
        lines.append(f"  {label:>11}  {'#' * bins[b]:<{max(bins.values())}}  {bins[b]}")
    lost = Counter()
    messages = {}
    ungradable = {r["submission"]: _ungradable(r) for r in results}
    for r in results:
        if ungradable[r["submission"]]:
            continue
        for k, t in r["todos"].items():
            if not t["passed"]:
                lost[k] += 1
                messages.setdefault(k, Counter())[_shape(t["message"])] += 1
    lines += ["", "TODOs lost most often:" if lost else "No TODO lost points (among the graded submissions)."]
    for k, count in lost.most_common():
        title = TODOS[int(k)].title if int(k) in TODOS else ""
        lines.append(f"  TODO {k} ({title}): lost by {count} of {n}")
        for shape, c in messages[k].most_common(top):
            lines.append(f"    {c}x {shape[:160]}")
    bad = {name: why for name, why in ungradable.items() if why}
    lines += ["", f"Not graded at all: {len(bad)}"]
    lines += [f"  {name}: {why[:200]}" for name, why in bad.items()]
    kinds = Counter()
    for r in results:
        for note in r.get("notes", []):
            kinds[next((kind for start, kind in NOTE_KINDS if note.startswith(start)), note[:40])] += 1
    if kinds:
        lines += ["", "Notes (see the feedback): " + "; ".join(f"{c}x {kind}" for kind, c in kinds.most_common())]
    return "\n".join(lines)


def write_summary(results: list, path) -> None:
    with atomic_output(path) as tmp:
        tmp.write_text(summary(results) + "\n", encoding="utf-8")
