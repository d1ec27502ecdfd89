"""Shared by the benchmark scripts: limit and describe the BLAS/OpenMP thread pools, name
the CPU."""

from __future__ import annotations

import platform


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


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"
