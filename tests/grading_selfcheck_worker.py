"""Run the self-check on many assignment files in one process (one ti.init); write the verdicts as JSON.

    python tests/grading_selfcheck_worker.py OUT.json FILE...

Each file gets {"results": {"1": {"passed", "message", ...}, ...}, "joint": ""}, from
rigid.grading.selfcheck.check_units against the answers file beside the repository's solution,
exactly what ``python FILE --check`` prints. test_grading_batch.py compares them with grade.py's.
"""
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.engine.units import load_units  # noqa: E402
from rigid.grading import answers  # noqa: E402
from rigid.grading.checks import init_grading_taichi  # noqa: E402
from rigid.grading.selfcheck import check_units  # noqa: E402


def main(out, *files):
    expected = answers.load(ROOT / answers.FILE_NAME)
    init_grading_taichi()  # as --check does (selfcheck.main)
    verdicts = {}
    for path in files:
        results, joint = check_units(load_units(path), expected)
        verdicts[path] = dict(results={str(k): r for k, r in results.items()}, joint=joint)
    Path(out).write_text(json.dumps(verdicts, indent=1, ensure_ascii=False))


if __name__ == "__main__":
    main(*sys.argv[1:])
