"""The ``--reduced`` and ``--cutoff-hz`` options of the commands that make runs."""

from __future__ import annotations

from rubdiag.cli._defaults import FromLibrary


def add_model_options(parser) -> None:
    """Add ``--reduced`` and ``--cutoff-hz`` to a command's parser."""
    parser.add_argument("--reduced", action="store_true",
                        help="simulate the reduced-order (Craig-Bampton) model: the contact "
                        "DOFs physical, the fixed-interface modes below the cutoff")
    parser.add_argument("--cutoff-hz", type=float, metavar="HZ", action=FromLibrary,
                        shows={"cutoff": "rubdiag.reduce:Reduction.cutoff_hz"},
                        help="with --reduced: keep the modes below HZ (default {cutoff}, "
                        "twice the 8x line at 6840 rpm)")


def reduction(args):
    """The :class:`~rubdiag.reduce.Reduction` the options ask for, or None (the full model);
    a bad combination or value raises a one-line ValueError naming the option."""
    if args.cutoff_hz is not None and not args.reduced:
        raise ValueError(f"--cutoff-hz {args.cutoff_hz:g} needs --reduced (the cutoff is the "
                         "reduced model's; without --reduced the full model runs)")
    if not args.reduced:
        return None
    from rubdiag.reduce import Reduction

    if args.cutoff_hz is None:
        return Reduction()
    try:
        return Reduction(cutoff_hz=args.cutoff_hz)
    except ValueError as exc:
        raise ValueError(f"--cutoff-hz: {exc}") from None
