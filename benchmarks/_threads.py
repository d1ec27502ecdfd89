"""Shared by the benchmark scripts: limit and describe the BLAS/OpenMP thread pools."""

from __future__ import annotations


def limit_threads(n: int | None) -> str:
    """Limit the loaded BLAS/OpenMP thread pools to ``n`` (None: leave them); describe them."""
    try:
        from threadpoolctl import threadpool_info, threadpool_limits
    except ImportError:
        if n is not None:
            raise SystemExit("--threads needs threadpoolctl (pip install threadpoolctl)") from None
        return "unknown (threadpoolctl not installed)"
    if n is not None:
        threadpool_limits(limits=n)
    return ", ".join(f"{p['internal_api']} {p['num_threads']}"
                     for p in threadpool_info()) or "none found"
