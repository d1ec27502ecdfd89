"""The README's picture: the study's case 1 with the serious gap, as ``rubdiag plot`` draws
it (shaft and casing waveforms, the orbit inside the clearance, the spectra with the rub's
lines marked, the contact forces and their status), saved small.

    .venv/bin/python docs/readme_figure.py       # -> docs/images/case1_serious.png
"""

from __future__ import annotations

import io
from pathlib import Path

import rubdiag

OUT = Path(__file__).resolve().parent / "images" / "case1_serious.png"


def main() -> None:
    rubdiag.pin_blas_kernels()      # first: before numpy loads OpenBLAS (the same bits anywhere)
    import matplotlib

    matplotlib.use("Agg")
    from PIL import Image

    from rubdiag.plotting import run_figure
    from rubdiag.simulation import Run, simulate

    figure = run_figure(simulate(Run.paper_case(1, gap_mm=1.9)))
    OUT.parent.mkdir(parents=True, exist_ok=True)
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=60)
    # a 64-colour palette keeps the picture small in the repository (line art loses nothing)
    Image.open(buffer).convert("RGB").quantize(64).save(OUT, optimize=True)
    print(f"wrote {OUT} ({OUT.stat().st_size / 1024:.0f} kB)")


if __name__ == "__main__":
    main()
