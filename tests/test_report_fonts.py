"""The report's PDF embeds a Unicode font (issue 15, item 10): the 14 standard fonts it used
are not embedded and have no ⁻, ᵀ or ‖, which viewers drew as black boxes."""
import shutil
import subprocess

import pytest

from conftest import ROOT

FORMULAS = ("I⁻¹ = R I0⁻¹ Rᵀ", "‖ΔL‖/‖L‖", "½[0, ω]⊗q", "τ")


def _fonts(pdf_path):
    """pdffonts' rows as (name, embedded) pairs; pypdf's view where poppler is not installed."""
    if shutil.which("pdffonts"):
        lines = subprocess.run(["pdffonts", str(pdf_path)], capture_output=True, text=True,
                               check=True).stdout.splitlines()[2:]
        return [(line.split()[0], line.split()[-5] == "yes") for line in lines]  # ... emb sub uni id gen
    from pypdf import PdfReader

    found = {}
    for page in PdfReader(pdf_path).pages:
        for font in page["/Resources"]["/Font"].values():
            font = font.get_object()
            descriptor = font.get("/FontDescriptor")
            found[str(font["/BaseFont"]).lstrip("/")] = descriptor is not None and any(
                key in descriptor.get_object() for key in ("/FontFile", "/FontFile2", "/FontFile3"))
    return sorted(found.items())


def _text(pdf_path) -> str:
    from pypdf import PdfReader

    return " ".join(" ".join(page.extract_text().split()) for page in PdfReader(pdf_path).pages)  # lines joined


def test_small_document_embeds_dejavu_and_keeps_the_characters(tmp_path):
    from rigid.report.document import Doc

    doc = Doc()
    doc.heading("Inverse inertia: I⁻¹ = R I0⁻¹ Rᵀ")
    doc.para("q += Δt ½[0, ω]⊗q; torque τ, **bold ‖x‖**, `code Rᵀ`")
    doc.bullets(["a bullet with ‖ΔL‖/‖L‖"])
    doc.table(["integrator", "‖ΔL‖/‖L‖ 10 s"], [["euler", "0.0e+00"]])
    doc.pdf(tmp_path / "a.pdf")
    fonts = _fonts(tmp_path / "a.pdf")
    names = [name.split("+")[-1] for name, _ in fonts]
    assert {"DejaVuSans", "DejaVuSans-Bold", "DejaVuSansMono"} <= set(names), fonts
    assert all(embedded for _, embedded in fonts), fonts  # no standard, unembedded font left
    text = _text(tmp_path / "a.pdf")
    for formula in FORMULAS:
        assert formula in text, (formula, text)
    assert "code Rᵀ" in text
    doc.pdf(tmp_path / "b.pdf")
    assert (tmp_path / "a.pdf").read_bytes() == (tmp_path / "b.pdf").read_bytes()  # still reproducible


def test_committed_report_embeds_its_fonts():
    pdf = ROOT / "report" / "report.pdf"
    fonts = _fonts(pdf)
    assert fonts and all(embedded for _, embedded in fonts), fonts
    text = _text(pdf)
    for formula in FORMULAS:
        assert formula in text, formula


@pytest.mark.skipif(shutil.which("apt-get") is None, reason="setup.sh installs poppler-utils with apt")
def test_setup_installs_pdffonts():
    assert "poppler-utils" in (ROOT / "scripts" / "setup.sh").read_text()
