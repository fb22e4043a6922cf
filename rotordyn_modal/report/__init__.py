"""A rotordynamic report (``rotordyn-modal report``): :func:`collect` runs the analyses a
standard asks for (``collect.py``, no figure), :func:`render_html` draws their figures and
writes one self-contained HTML page (``render.py``). docs/report.md lists the contents."""

from .collect import SECTIONS, STANDARDS, Criterion, ReportData, ReportInputs, collect
from .render import render_html

__all__ = ["SECTIONS", "STANDARDS", "Criterion", "ReportData", "ReportInputs", "collect", "render_html"]
