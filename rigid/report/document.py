"""A tiny document model written two ways: Markdown (report.md) and PDF (report.pdf).

The report's text is written once, as blocks; reportlab lays out the PDF
(``invariant=1``: the same blocks give the same bytes, no timestamps). The PDF's text is
set in DejaVu Sans (and Sans Mono for code), the TTFs matplotlib ships, embedded as
subsets: the 14 standard PDF fonts are not embedded and have no glyphs for ⁻, ᵀ or ‖,
which viewers draw as black boxes.
"""
from __future__ import annotations

import html
from pathlib import Path


class Doc:
    def __init__(self):
        self.blocks: list[tuple] = []

    def heading(self, text: str, level: int = 1):
        self.blocks.append(("heading", text, level))

    def para(self, text: str):
        """A paragraph; `code` and **bold** spans as in Markdown."""
        self.blocks.append(("para", text))

    def bullets(self, items: list[str]):
        self.blocks.append(("bullets", items))

    def table(self, header: list[str], rows: list[list]):
        self.blocks.append(("table", header, [[str(c) for c in r] for r in rows]))

    def image(self, path: Path, caption: str, width_cm: float = 16):
        self.blocks.append(("image", Path(path), caption, width_cm))

    # -- Markdown ---------------------------------------------------------------------------
    def markdown(self, base: Path) -> str:
        out = []
        for block in self.blocks:
            kind = block[0]
            if kind == "heading":
                out.append("#" * block[2] + " " + block[1])
            elif kind == "para":
                out.append(block[1])
            elif kind == "bullets":
                out.append("\n".join(f"- {item}" for item in block[1]))
            elif kind == "table":
                header, rows = block[1], block[2]
                lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
                lines += ["| " + " | ".join(r) + " |" for r in rows]
                out.append("\n".join(lines))
            elif kind == "image":
                out.append(f"![{block[2]}]({block[1].relative_to(base).as_posix()})\n\n*{block[2]}*")
        return "\n\n".join(out) + "\n"

    # -- PDF --------------------------------------------------------------------------------
    def pdf(self, path: Path) -> None:
        from reportlab.lib import colors
        from reportlab.lib.pagesizes import A4
        from reportlab.lib.styles import getSampleStyleSheet
        from reportlab.lib.units import cm
        from reportlab.platypus import Image, Paragraph, SimpleDocTemplate, Spacer, Table, TableStyle

        styles = getSampleStyleSheet()
        _use_embedded_fonts(styles)
        small = styles["BodyText"].clone("small", fontSize=7.5, leading=9)
        story = []
        for block in self.blocks:
            kind = block[0]
            if kind == "heading":
                story.append(Paragraph(_inline(block[1]), styles[f"Heading{min(block[2], 3)}"]))
            elif kind == "para":
                story.append(Paragraph(_inline(block[1]), styles["BodyText"]))
            elif kind == "bullets":
                for item in block[1]:
                    story.append(Paragraph("• " + _inline(item), styles["BodyText"]))
            elif kind == "table":
                data = [[Paragraph(_inline(c), small) for c in row] for row in [block[1], *block[2]]]
                table = Table(data, repeatRows=1)
                table.setStyle(TableStyle([("FONTNAME", (0, 0), (-1, -1), FONTS["Helvetica"][0]),
                                           ("GRID", (0, 0), (-1, -1), 0.3, colors.grey),
                                           ("BACKGROUND", (0, 0), (-1, 0), colors.whitesmoke),
                                           ("VALIGN", (0, 0), (-1, -1), "TOP")]))
                story += [table, Spacer(1, 0.3 * cm)]
            elif kind == "image":
                from PIL import Image as PILImage

                with PILImage.open(block[1]) as im:
                    w, h = im.size
                width = block[3] * cm
                story += [Image(str(block[1]), width=width, height=width * h / w),
                          Paragraph(f"<i>{_inline(block[2])}</i>", small), Spacer(1, 0.3 * cm)]
        SimpleDocTemplate(str(path), pagesize=A4, invariant=1, title="Assignment 3 report",
                          initialFontName=FONTS["Helvetica"][0],  # else the page resources list Helvetica
                          leftMargin=2 * cm, rightMargin=2 * cm, topMargin=1.8 * cm,
                          bottomMargin=1.8 * cm).build(story)


# reportlab's standard fonts -> the embedded TTFs that replace them (file names in matplotlib's fonts/ttf).
FONTS = {"Helvetica": ("DejaVuSans", "DejaVuSans.ttf"),
         "Helvetica-Bold": ("DejaVuSans-Bold", "DejaVuSans-Bold.ttf"),
         "Helvetica-Oblique": ("DejaVuSans-Oblique", "DejaVuSans-Oblique.ttf"),
         "Helvetica-BoldOblique": ("DejaVuSans-BoldOblique", "DejaVuSans-BoldOblique.ttf"),
         "Courier": ("DejaVuSansMono", "DejaVuSansMono.ttf")}
MONO = FONTS["Courier"][0]


def _use_embedded_fonts(styles) -> None:
    """Register the DejaVu TTFs (once) and set every style's font to them."""
    import matplotlib
    from reportlab.pdfbase import pdfmetrics
    from reportlab.pdfbase.ttfonts import TTFont

    folder = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
    for name, file in FONTS.values():
        if name not in pdfmetrics.getRegisteredFontNames():
            pdfmetrics.registerFont(TTFont(name, str(folder / file)))
    pdfmetrics.registerFontFamily(FONTS["Helvetica"][0], normal=FONTS["Helvetica"][0],
                                  bold=FONTS["Helvetica-Bold"][0], italic=FONTS["Helvetica-Oblique"][0],
                                  boldItalic=FONTS["Helvetica-BoldOblique"][0])
    for style in styles.byName.values():
        for attribute in ("fontName", "bulletFontName"):
            font = getattr(style, attribute, None)
            if font in FONTS:
                setattr(style, attribute, FONTS[font][0])


def _inline(text: str) -> str:
    """Markdown `code` and **bold** to reportlab's mini-HTML."""
    import re

    text = html.escape(text, quote=False)
    text = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", text)
    return re.sub(r"`(.+?)`", rf"<font face='{MONO}'>\1</font>", text)
