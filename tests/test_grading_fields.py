"""rigid.grading.original.fields: the versions of a graded file share their fields, each from zero.

Run in a child process: install() changes how this Taichi process declares fields."""
import json
import subprocess
import sys

from conftest import ROOT

SCRIPT = r"""
import json, sys
import taichi as ti
ti.init(arch=ti.cpu, log_level=ti.ERROR, advanced_optimization=False)
from rigid.grading.original import fields
fields.install(ti)

def version(n=5):
    fields.new_version()
    v = ti.Vector.field(3, dtype=ti.f32, shape=n)
    s = ti.field(float, shape=())
    m = ti.types.matrix(3, 3, float).field(shape=())
    lazy = ti.field(ti.i32)          # placed later: never shared
    ti.root.dense(ti.i, 4).place(lazy)
    return v, s, m, lazy

first = version()
first[0].fill(2.0); first[1][None] = 3.0; first[2].fill(float("nan")); first[3].fill(7)
second = version()
other = version(n=6)                 # another shape: a field of its own
print(json.dumps(dict(
    same=[a is b for a, b in zip(first, second)],
    zeroed=[float(abs(second[0].to_numpy()).sum()), float(second[1][None]), float(abs(second[2].to_numpy()).sum())],
    lazy_fresh=int(second[3].to_numpy().sum()),
    other_shape=[other[0] is first[0], other[0].shape[0], other[1] is first[1]])))
"""


def test_versions_share_zeroed_fields_and_differ_where_the_declaration_does():
    proc = subprocess.run([sys.executable, "-c", SCRIPT], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    got = json.loads(proc.stdout.strip().splitlines()[-1])
    assert got["same"] == [True, True, True, False]  # the shape-less field is declared anew
    assert got["zeroed"] == [0.0, 0.0, 0.0]  # as a new field: values, and NaNs, gone
    assert got["lazy_fresh"] == 0
    assert got["other_shape"] == [False, 6, True]  # a changed declaration gets its own; the next still matches
