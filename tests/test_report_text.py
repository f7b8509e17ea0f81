"""The report's words (issue 21, item 6): figures, not the project's targets; a formula that does
not wrap; the flip caption says why its period differs from the validation table's; the
recording stills' overlay large enough to read in print."""
import json

from conftest import ROOT


class _Doc:
    """Collects what the report's writers put into a document."""

    def __init__(self):
        self.texts = []

    def heading(self, text, level=1):
        self.texts.append(text)

    def para(self, text):
        self.texts.append(text)

    def bullets(self, items):
        self.texts.extend(items)

    def table(self, header, rows):
        self.texts.append(" ".join(map(str, header + [c for r in rows for c in r])))

    def image(self, path, caption, width_cm=16):
        self.texts.append(caption)


def test_the_report_states_figures_not_the_projects_targets(tmp_path):
    from rigid.report import text, text_many

    doc = _Doc()
    text_many._bench(doc, tmp_path, json.loads((ROOT / "report" / "bench_many.json").read_text()))
    words = " ".join(doc.texts + text.BONUS + text.IDEAS).lower()
    assert "times as fast as mujoco" in words and "frames per second" in words
    for phrase in ("target", "missed", "goal"):
        assert phrase not in words, phrase


def test_the_update_formulas_never_wrap(tmp_path):
    """The PDF wrapped "q += Δt ½[0, ω]⊗q" after "[0,"; each formula is one unbreakable run."""
    from pypdf import PdfReader

    from rigid.report.document import Doc
    from rigid.report.text import INTRO

    for formula in ("q += Δt ½[0, ω]⊗q", "I⁻¹ = R I0⁻¹ Rᵀ", "x += Δt P/M"):
        assert formula.replace(" ", "\u00a0") in INTRO, formula
    doc = Doc()
    for width in range(6):  # the paragraph after prefixes of several lengths: the line breaks fall elsewhere
        doc.para("word " * (7 * width) + INTRO)
    doc.pdf(tmp_path / "intro.pdf")
    lines = [" ".join(line.replace("\u00a0", " ").split())
             for page in PdfReader(tmp_path / "intro.pdf").pages for line in page.extract_text().splitlines()]
    broken = [line for line in lines if line.rstrip().endswith(("[0,", "½[0,", "+=", "Δt", "I0⁻¹", "="))]
    assert not broken, broken
    assert sum("½[0, ω]⊗q" in line for line in lines) == 6


def test_the_flip_caption_explains_the_validation_tables_smaller_figure():
    """The figure said 3.295 s / 7.36 %, the table +5.6 % for the same Δt, with no word on why: the
    table averages a shorter run, and explicit Euler lengthens each flip (not float32: both
    precisions give the same periods)."""
    from rigid.report.text import flip_caption

    validation = json.loads((ROOT / "report" / "validation.json").read_text())
    crossings = [0.76798, 2.34210, 3.96110, 5.63172, 7.36294]
    caption = flip_caption(dict(period=3.295, reference_period=3.069, crossings=crossings, dt=1e-3), validation)
    assert "3.295 s on average" in caption and "(+7.36%)" in caption
    assert "each flip takes longer than the last (3.193, 3.290, 3.402 s)" in caption
    assert "the validation table's +5.6% (Δt 0.001) averages a shorter run's first flips (3.241 s)" in caption
    assert "float32" in caption and "float64" in caption


def test_the_stills_overlay_is_legible_in_print():
    """The text of a recording (--record) printed in the report: at least 7 pt (it was ~4)."""
    from rigid.report.text import STILL_WIDTH_CM
    from rigid.view.imaging import TextOverlay

    for width, height in ((640, 360), (1280, 720), (320, 180)):
        points = TextOverlay(height).size * STILL_WIDTH_CM / width * 72 / 2.54
        assert points >= 7, (width, height, points)
