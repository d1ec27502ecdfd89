"""Commands of the study's reproduction: ``table2`` and ``plot``."""

from __future__ import annotations

import sys
from pathlib import Path

from rubdiag.cli._defaults import FromLibrary
from rubdiag.cli._model import add_model_options, reduction
from rubdiag.cli._paths import add_rig_option
from rubdiag.cli._quiet import add_quiet_option

#: the function ``table2`` calls, whose keywords the options stand for
_TABLE2 = "rubdiag.paper._table2:table2."


def register(sub) -> None:
    p = sub.add_parser(
        "table2", help="reproduce the study's Table 2 and Figures 5-10",
        description="Simulate the study's four rub cases (case 1 at the first and case 2 at "
        "the second forward critical speed, g0 = 2.3 mm light and 1.9 mm serious) in "
        "parallel, extract their features and write DIR/table2.csv, DIR/table2.md, "
        "DIR/features.csv and the figures fig5…fig10 (PNG), ours beside the study's values. "
        "Finished runs are kept in DIR/runs/ and reused: an interrupted reproduction resumes.")
    p.add_argument("--out", type=Path, default=Path("out"), help="output folder (default out)")
    p.add_argument("--jobs", type=int, help="parallel processes (default: all cores)")
    p.add_argument("--duration-s", type=float, action=FromLibrary,
                   default_of=_TABLE2 + "duration_s",
                   help="total simulated time per case (s, default {default})")
    p.add_argument("--discard-s", type=float, action=FromLibrary,
                   default_of=_TABLE2 + "discard_s",
                   help="start left out of the statistics (s, default {default})")
    add_rig_option(p)
    p.add_argument("--no-figures", action="store_true", help="write the tables only")
    add_model_options(p)
    add_quiet_option(p, help="no progress on stderr (on a terminal a bar with an ETA; "
                     "elsewhere, for logs, a line per case reused or finished)")
    p.set_defaults(func=_table2)

    p = sub.add_parser(
        "plot", help="figures of a saved simulation result",
        description="Draw the six-panel figure of a saved run (as the study's Figs. 7-10: "
        "shaft and casing waveforms (µm), orbit with the clearance circle (mm), amplitude "
        "spectra with the detected features, normal forces (N) and contact status).")
    p.add_argument("result", type=Path, help="a result file written by `rubdiag simulate "
                   "--out` or `rubdiag table2` (.npz)")
    p.add_argument("--out", type=Path, default=Path("out"), help="output folder (default out)")
    p.set_defaults(func=_plot)


def _table2(args) -> int:
    import time

    from rubdiag.cli._paths import load_rig, output_folder
    from rubdiag.paper import table2
    from rubdiag.simulation import SimulationDiverged

    if args.jobs is not None and args.jobs < 1:
        raise ValueError(f"--jobs = {args.jobs} is out of range (allowed: >= 1)")
    start = time.perf_counter()
    options = {"reduction": reduction(args)}
    if args.rig is not None:
        options["rig"] = load_rig(args.rig)
    output_folder(args.out)
    try:
        table = table2(args.out, jobs=args.jobs, duration_s=args.duration_s,
                       discard_s=args.discard_s, figures=not args.no_figures,
                       progress=not args.quiet,
                       log=(lambda message: None) if args.quiet else None, **options)
    except SimulationDiverged as exc:   # finished cases stay saved in DIR/runs
        raise ValueError(str(exc)) from None
    print((args.out / "table2.md").read_text(encoding="utf-8"))
    print(f"wrote {args.out}/table2.csv, table2.md, features.csv"
          f"{'' if args.no_figures else ' and fig5…fig10 PNGs'} in "
          f"{time.perf_counter() - start:.0f} s", file=sys.stderr)
    return 0 if (table["contact1_max_force_n"] > 0).all() else 1


def _plot(args) -> int:
    from rubdiag.cli._paths import input_file, load_result, output_folder
    from rubdiag.plotting import save_run_figures

    input_file(args.result, None, "a result file")   # a typo must not leave a new folder
    output_folder(args.out)
    result = load_result(args.result)
    paths = save_run_figures(result, args.out, stem=args.result.stem)
    print("wrote " + ", ".join(str(p) for p in paths), file=sys.stderr)
    return 0
