"""The study's reproduction: Table 2 and Figures 5-10, beside the study's own values."""

from rubdiag.paper.describe import describe_spectrum
from rubdiag.paper.table2 import CASES, PaperCase, paper_values, reproduce, table2

__all__ = ["CASES", "PaperCase", "describe_spectrum", "paper_values", "reproduce", "table2"]
