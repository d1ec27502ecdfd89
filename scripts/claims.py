#!/usr/bin/env python
"""The study's claims: measure each one from a reproduction, keep the verdict in
``data/claims.csv``, from which the documentation renders its claims table
(``docs/generate.py``, :func:`render`).

``data/claims.csv`` holds one row per claim of the study (section 3, Table 2), with the
quantity we measure and a tolerance fixed from the study's wording before anything was
measured (see ``data/README.md``). This script fills in ``measured``, ``detail`` and
``status``; a claim that is not reproduced needs a ``reason``, written by hand (the script
keeps it, and clears it when the claim holds). ``tests/paper/test_table2.py`` tests every
claim with the same measurement (:func:`measure`) and the tolerance from the table, those not
reproduced as strict xfails with their reason.

A claim is measured either on the Table 2 reproduction (``data`` = ``table``: one run per
cell) or on the five start histories of a case-1 cell (``ensemble case 1 light|serious``:
the gap ramp 0.1 s ± 2 %, :func:`rubdiag.paper._ensemble`), where ``measured`` counts the runs
whose per-run quantity lies in ``per_run``.

Usage::

    python scripts/claims.py                       # measure, write the table
    python scripts/claims.py --check               # measure and compare; exit 1 if different
    python scripts/claims.py --no-measure          # statuses from stored measurements
    python scripts/claims.py --no-measure --check  # fast: do the statuses follow?

Measuring runs Table 2 (``rubdiag.paper._table2``, whose runs are kept in ``OUT/runs``) and
the two case-1 ensembles (10 runs, kept in ``OUT/claims_ensemble.csv`` with the fingerprint
of their run descriptions): a few minutes on 2 cores the first time.
"""

from __future__ import annotations

import argparse
import csv
import difflib
import hashlib
import math
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

ROOT = Path(__file__).resolve().parents[1]
CLAIMS = ROOT / "data" / "claims.csv"
COLUMNS = ("id", "source", "claim", "quantity", "data", "study", "per_run", "tolerance",
           "rule", "measured", "detail", "status", "reason")
HOLDS, NOT_REPRODUCED = "holds", "not reproduced"
#: The case-1 cells whose start histories are compared, (case, g0 in mm).
ENSEMBLE_CASES = ((1, 2.3), (1, 1.9))
INTENSITY = {2.3: "light", 1.9: "serious"}


# --- tolerances -----------------------------------------------------------------------------
@dataclass(frozen=True)
class Interval:
    """``[lo, hi]`` with each end open or closed; an infinite end means unbounded (a ratio
    over a line that is absent, ``inf``, lies in ``(1, inf)``)."""

    lo: float
    hi: float
    lo_closed: bool = True
    hi_closed: bool = True

    def __contains__(self, x) -> bool:
        x = float(x)
        if math.isnan(x):
            return False
        above = x >= self.lo if self.lo_closed or math.isinf(self.lo) else x > self.lo
        below = x <= self.hi if self.hi_closed or math.isinf(self.hi) else x < self.hi
        return above and below

    def __str__(self) -> str:
        return (f"{'[' if self.lo_closed else '('}{_number(self.lo)}, {_number(self.hi)}"
                f"{']' if self.hi_closed else ')'}")


_INTERVAL = re.compile(r"^([\[(])\s*(\S+?)\s*,\s*(\S+?)\s*([\])])$")
_PLUS_MINUS = re.compile(r"^±\s*([0-9.]+)\s*(%?)$")
_LEADING_NUMBER = re.compile(r"^[-+]?[0-9]+(?:\.[0-9]+)?")


def study_number(claim: dict) -> float | None:
    """The study's value as a number (the leading number of ``study``), or None."""
    m = _LEADING_NUMBER.match(claim["study"])
    return float(m.group()) if m else None


def interval(spec: str, centre: float | None = None) -> Interval:
    """Parse ``[a, b]`` / ``(a, b]`` … or ``±15 %`` / ``± 2`` around ``centre``."""
    m = _INTERVAL.match(spec.strip())
    if m:
        return Interval(float(m[2]), float(m[3]), m[1] == "[", m[4] == "]")
    m = _PLUS_MINUS.match(spec.strip())
    if m:
        if centre is None:
            raise ValueError(f"tolerance {spec!r} needs a numeric study value")
        half = float(m[1]) * (abs(centre) / 100 if m[2] else 1.0)
        return Interval(centre - half, centre + half)
    raise ValueError(f"not a tolerance: {spec!r} (want [a, b], (a, b], ±15 % or ± 2)")


def tolerance(claim: dict) -> Interval:
    """The interval ``measured`` must lie in for the claim to hold."""
    return interval(claim["tolerance"], study_number(claim))


def per_run(claim: dict) -> Interval:
    """The interval a start history's quantity must lie in to count (ensemble claims)."""
    return interval(claim["per_run"], study_number(claim))


def verdict(claim: dict, measured=None) -> str:
    """``holds`` when ``measured`` (default: the stored value) lies in the tolerance."""
    value = claim["measured"] if measured is None else measured
    return HOLDS if value != "" and float(value) in tolerance(claim) else NOT_REPRODUCED


def ensemble_intensity(claim: dict) -> str | None:
    """``light`` / ``serious`` for a claim measured on a case-1 ensemble, else None."""
    data = claim["data"]
    if data == "table":
        return None
    m = re.fullmatch(r"ensemble case 1 (light|serious)", data)
    if not m:
        raise ValueError(f"{claim['id']}: data {data!r} is neither 'table' nor "
                         "'ensemble case 1 light|serious'")
    return m[1]


# --- the table ------------------------------------------------------------------------------
def read(path: Path = CLAIMS) -> list[dict]:
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    if rows and tuple(rows[0]) != COLUMNS:
        raise ValueError(f"{path}: columns {tuple(rows[0])}, want {COLUMNS}")
    return rows


def write(claims: list[dict], path: Path = CLAIMS) -> None:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(claims)


def _number(x: float) -> str:
    """4 significant digits, ``inf``, ``nan``; integers without a point."""
    x = float(x)
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    if math.isnan(x):
        return "nan"
    return f"{x:.4g}"


# --- measurements ---------------------------------------------------------------------------
CELLS = {"1 light": (1, "light"), "1 serious": (1, "serious"),
         "2 light": (2, "light"), "2 serious": (2, "serious")}


def cell(table, name: str) -> dict:
    """One Table 2 row with its full feature row (contact statistics, spectra)."""
    case, intensity = CELLS[name]
    row = table[(table.case == case) & (table.intensity == intensity)].iloc[0]
    return {**table.attrs["features"].loc[row.name].to_dict(), **row.to_dict()}


def _value(column: str, name: str):
    return lambda t: (cell(t, name)[column], "")


def _ratio(column: str, num: str, den: str, den_column: str | None = None):
    def measure(t):
        a, b = cell(t, num)[column], cell(t, den)[den_column or column]
        return a / b, f"{_number(a)} / {_number(b)}"
    return measure


def _smallest(*measures):
    def measure(t):
        values = [m(t) for m in measures]
        return min(v for v, _ in values), "; ".join(d for _, d in values)
    return measure


def _lines(r: dict) -> list[float]:
    """Every line amplitude of a shaft feature row but 1×: orders, 1/3 orders, sideband and
    combination lines (absent lines are 0, unmeasurable ones NaN: left out)."""
    keep = re.compile(r"shaft_(amp_\w+|sb_\d+x_(lower|upper)|combo_amp_[ab])$")
    return [v for k, v in r.items()
            if keep.match(k) and k != "shaft_amp_1x" and not math.isnan(v)]


def predominance(r: dict) -> float:
    """The shaft 1× line over the largest other line."""
    other = max(_lines(r))
    return math.inf if other == 0 else r["shaft_amp_1x"] / other


def continuous_rms(r: dict, n: int) -> float:
    """RMS over n× ± 0.25× without the n× line and without its sideband lines (each line
    of amplitude A carries A²/2 of the band's power)."""
    bb = r[f"shaft_bb_{n}x_rms"]
    sidebands = sum(0.0 if math.isnan(a) else a * a
                    for a in (r[f"shaft_sb_{n}x_lower"], r[f"shaft_sb_{n}x_upper"]))
    return math.sqrt(max(bb * bb - sidebands / 2, 0.0))


def hump(r: dict) -> float:
    """At least 1 when the continuous part near 4× holds at least the 4× line's RMS and
    exceeds the continuous parts near 3× and 5× (the study's "wide continuous peak")."""
    b3, b4, b5 = (continuous_rms(r, n) for n in (3, 4, 5))
    if b4 == 0:
        return 0.0
    line = r["shaft_amp_4x"] / math.sqrt(2)
    return min(math.inf if line == 0 else b4 / line,
               math.inf if max(b3, b5) == 0 else b4 / max(b3, b5))


#: Table claims: id -> f(table) -> (value, detail).
TABLE: dict[str, Callable] = {
    "C1a": _value("rotor_max_y_mm", "1 light"),
    "C1e": _smallest(*(_ratio("contact1_mean_force_sticking_n", c, c,
                              "contact1_mean_force_sliding_n") for c in CELLS)),
    "C1f": _ratio("rotor_max_y_mm", "1 serious", "1 light"),
    "C1g": _ratio("casing_max_y_um", "1 serious", "1 light"),
    "C1h": _ratio("contact1_n_episodes", "1 serious", "1 light"),
    "C1m": _ratio("contact1_max_force_n", "1 serious", "1 light"),
    "C1n": _ratio("contact1_sticking_share", "1 serious", "1 light"),
    "C1o": _value("contact1_sticking_share", "1 light"),
    "C2a": _ratio("casing_max_y_um", "2 light", "1 light"),
    "C2b": _ratio("casing_max_y_um", "2 serious", "1 serious"),
    "C2c": _ratio("rotor_max_y_mm", "2 light", "2 light", "gap_mm"),
    "C2d": _value("shaft_combo_order", "2 light"),
    "C2e": _value("shaft_combo_order", "2 serious"),
    "C2f": _value("shaft_combo_fa_hz", "2 light"),
    "C2g": _value("shaft_combo_fa_hz", "2 serious"),
    "C2h": lambda t: (abs(cell(t, "2 serious")["shaft_combo_fa_hz"]
                          - cell(t, "2 light")["shaft_combo_fa_hz"]), ""),
    "C2i": _ratio("contact1_max_force_n", "2 light", "1 light"),
    "C2j": _ratio("contact1_max_force_n", "2 serious", "1 serious"),
    "C2k": _smallest(_ratio("contact1_n_episodes", "2 light", "1 light"),
                     _ratio("contact1_n_episodes", "2 serious", "1 serious")),
    "C2l": _value("contact1_sticking_share", "2 light"),
    "C2m": _value("contact1_sticking_share", "2 serious"),
    "C2n": _ratio("contact1_max_force_n", "2 serious", "2 light"),
}
# Table 2's numbers, cell by cell: C3a … C7d
for _prefix, _column in (("C3", "casing_max_y_um"), ("C4", "contact1_max_force_n"),
                         ("C5", "contact1_min_force_n"), ("C6", "contact1_sliding_entries"),
                         ("C7", "contact1_sticking_entries")):
    for _letter, _name in zip("abcd", CELLS, strict=True):
        TABLE[_prefix + _letter] = _value(_column, _name)

#: Ensemble claims: id -> f(feature row of one start history) -> the per-run quantity.
RUNS: dict[str, Callable[[dict], float]] = {
    "C1b": predominance,
    "C1c": hump,
    "C1d": lambda r: r["shaft_sb_4x_delta_hz"],
    "C1i": lambda r: r["shaft_amp_1p5x"],
    "C1j": lambda r: r["shaft_amp_3p5x"],
    "C1k": lambda r: max(r["shaft_amp_1p5x"], r["shaft_amp_3p5x"]),
    "C1l": lambda r: r["shaft_sb_4x_delta_hz"],
}


def per_run_values(claim: dict, ensemble) -> list[float]:
    """The per-run quantity of an ensemble claim, one per start history (gap ramp order)."""
    rows = ensemble[ensemble.intensity == ensemble_intensity(claim)].sort_values("gap_ramp_s")
    return [float(RUNS[claim["id"]](r)) for r in rows.to_dict("records")]


def measure(claim: dict, table, ensemble=None) -> tuple[float, str]:
    """``(value, detail)`` of one claim: on ``table`` (:func:`rubdiag.paper._table2`'s, with
    its ``features``) or, for an ensemble claim, the number of start histories in
    ``ensemble`` (:func:`case1_ensemble`) whose quantity lies in ``per_run``."""
    if ensemble_intensity(claim) is None:
        value, detail = TABLE[claim["id"]](table)
        return float(value), detail
    values = per_run_values(claim, ensemble)
    inside = per_run(claim)
    k = sum(v in inside for v in values)
    return float(k), f"of {len(values)}; per run: " + ", ".join(_number(v) for v in values)


def with_intensity(ensemble):
    """The ensemble's rows labelled ``light`` / ``serious`` by their gap."""
    ensemble = ensemble.copy()
    ensemble["intensity"] = [INTENSITY[g] for g in ensemble.gap_mm]
    return ensemble


def case1_ensemble(jobs: int | None = 2, cache: Path | None = None):
    """The two case-1 cells from the five default start histories, labelled by intensity;
    kept in ``cache`` (a CSV) and reused while the run descriptions are the same."""
    import pandas as pd

    from rubdiag.paper import GAP_RAMPS_S, ensemble
    from rubdiag.simulation import Run

    runs = [Run.paper_case(c, g, gap_ramp_s=r) for c, g in ENSEMBLE_CASES for r in GAP_RAMPS_S]
    key = hashlib.sha256("\n".join(map(repr, runs)).encode()).hexdigest()
    if cache is not None and cache.is_file():
        with open(cache, encoding="utf-8") as fh:
            if fh.readline().strip() == f"# {key}":
                return with_intensity(pd.read_csv(fh))
    table = ensemble(list(ENSEMBLE_CASES), jobs=jobs)
    if cache is not None:
        cache.parent.mkdir(parents=True, exist_ok=True)
        with open(cache, "w", encoding="utf-8") as fh:
            fh.write(f"# {key}\n")
            table.to_csv(fh, index=False)
    return with_intensity(table)


def measure_all(claims: list[dict], out: Path, jobs: int) -> list[dict]:
    """Measure every claim on a reproduction in ``out`` (Table 2's runs reused)."""
    from rubdiag.paper import table2

    table = table2(out, jobs=jobs, figures=False)
    ensemble = case1_ensemble(jobs, out / "claims_ensemble.csv")
    measured = []
    for claim in claims:
        value, detail = measure(claim, table, ensemble)
        measured.append({**claim, "measured": _number(value), "detail": detail})
    return measured


def with_status(claims: list[dict]) -> list[dict]:
    """Status from the stored measurement; a holding claim keeps no reason."""
    rows = []
    for claim in claims:
        status = verdict(claim) if claim["measured"] != "" else ""
        rows.append({**claim, "status": status,
                     "reason": "" if status == HOLDS else claim["reason"]})
    return rows


# --- the table ---------------------------------------------------------------------------------
def _cell_text(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def tolerance_text(claim: dict) -> str:
    """The tolerance as written and, for ``±`` forms, the interval it gives."""
    tol = claim["tolerance"]
    if tol.startswith("±"):
        t = tolerance(claim)
        tol = f"{tol}: {_number(t.lo)} … {_number(t.hi)}"
    if ensemble_intensity(claim) is None:
        return tol
    runs = claim["per_run"]
    if runs.startswith("±"):
        p = per_run(claim)
        runs = f"{_number(p.lo)} … {_number(p.hi)}"
    return f"per run in {runs}; runs in {tol}"


def measured_text(claim: dict) -> str:
    measured, detail = claim["measured"], claim["detail"]
    if measured == "":
        return "not measured"
    if ensemble_intensity(claim) is not None:
        return f"{measured} {detail}"
    if claim["tolerance"].startswith("±") and claim["tolerance"].endswith("%"):
        deviation = float(measured) / study_number(claim) - 1
        detail = f"{deviation:+.0%}".replace("%", " %") + (f"; {detail}" if detail else "")
    return f"{measured} ({detail})" if detail else measured


def render(claims: list[dict]) -> str:
    """The claims table (Markdown): one row per claim, then the count."""
    lines = ["| id | the study says (where) | we measure | study | tolerance | measured | "
             "verdict |", "|---|---|---|---|---|---|---|"]
    for c in claims:
        verdict_text = ("holds" if c["status"] == HOLDS else
                        f"**xfail**: {c['reason']}" if c["status"] == NOT_REPRODUCED else
                        "not measured")
        lines.append("| " + " | ".join(_cell_text(x) for x in (
            c["id"], f"{c['claim']} ({c['source']})", c["quantity"], c["study"],
            tolerance_text(c), measured_text(c), verdict_text)) + " |")
    n_hold = sum(c["status"] == HOLDS for c in claims)
    if n_hold == len(claims):
        summary = f"Every claim holds ({n_hold} of {n_hold})."
    else:
        summary = (f"**{n_hold} of {len(claims)} claims hold; {len(claims) - n_hold} are not "
                   "reproduced** (strict xfails in `tests/paper/test_table2.py`, with the "
                   "reason above).")
    return "\n".join(lines) + "\n\n" + summary + "\n"


# --- command line ---------------------------------------------------------------------------
def _diff(a: str, b: str, name: str) -> str:
    return "".join(difflib.unified_diff(a.splitlines(True), b.splitlines(True),
                                        f"{name} (stored)", f"{name} (now)"))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true",
                        help="compare instead of writing; exit 1 on any difference")
    parser.add_argument("--no-measure", action="store_true",
                        help="take the stored measurements (no simulation)")
    parser.add_argument("--out", type=Path, default=ROOT / "out",
                        help="reproduction folder (runs reused from OUT/runs); default: out")
    parser.add_argument("--jobs", type=int, default=2, help="processes (default 2)")
    parser.add_argument("--claims", type=Path, default=CLAIMS)
    args = parser.parse_args(argv)

    stored = read(args.claims)
    claims = stored if args.no_measure else measure_all(stored, args.out, args.jobs)
    claims = with_status(claims)
    missing = [c["id"] for c in claims if c["status"] == NOT_REPRODUCED and not c["reason"]]

    def table_text(rows):
        from io import StringIO

        buffer = StringIO()
        csv.DictWriter(buffer, COLUMNS, lineterminator="\n").writerows(rows)
        return buffer.getvalue()

    if args.check:
        problems = [d for d in (_diff(table_text(stored), table_text(claims), "claims.csv"),)
                    if d]
        if missing:
            problems.append("not reproduced without a reason: " + ", ".join(missing))
        print("\n".join(problems) or "claims table is current")
        return 1 if problems else 0
    write(claims, args.claims)
    for c in claims:
        print(f"{c['id']:4} {c['status']:15} {c['measured']:>8}  {c['detail']}")
    if missing:
        print("write a reason for: " + ", ".join(missing), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
