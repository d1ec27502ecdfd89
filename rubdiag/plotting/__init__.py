"""Figures (a leaf layer: nothing else in rubdiag imports it). Matplotlib, Agg backend."""
