"""The study's reproduction: Table 2 and Figures 5-10, beside the study's own values."""

from rubdiag.paper._describe import describe_spectrum
from rubdiag.paper._ensemble import GAP_RAMPS_S, ensemble
from rubdiag.paper._table2 import CASES, PaperCase, paper_values, reproduce, table2

__all__ = [
    "CASES",
    "GAP_RAMPS_S",
    "PaperCase",
    "describe_spectrum",
    "ensemble",
    "paper_values",
    "reproduce",
    "table2",
]
