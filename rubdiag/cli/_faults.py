"""Options that put the faults that look like rub into a run: gravity, a crack, misalignment,
a loose pedestal."""

from __future__ import annotations

import math

from rubdiag.cli._defaults import FromLibrary

#: where a dataset design's fixed fault settings are defined (the coupling's, here)
_SETTINGS = "rubdiag.dataset._faults:FaultSettings."


def add_fault_options(p) -> None:
    """Add the fault options to a command's parser (``simulate``, ``runup``)."""
    g = p.add_argument_group(
        "faults beside (or instead of) rub",
        "a breathing crack, a misaligned coupling, a loose pedestal (documentation: Faults that "
        "look like rub); "
        "without --gap-mm the run has no blade-casing contact")
    g.add_argument("--gravity-m-s2", type=float,
                   help="gravity along y (m/s^2; -9.81 pulls towards -y): the static load a "
                   "crack breathes under; the run starts from its static deflection")
    g.add_argument("--crack-element", type=int,
                   help="shaft element (0-based, axial order) with a breathing crack")
    g.add_argument("--crack-depth", type=float, default=0.3,
                   help="crack depth ratio a/D in (0, 0.5] (default 0.3)")
    g.add_argument("--crack-law", metavar="LAW", action=FromLibrary,
                   default_of="rubdiag.simulation._faults:Crack.law",
                   choices_of="rubdiag.simulation._crack:LAWS",
                   help="breathing law, one of {choices}: Mayes (cosine of the angle) or "
                   "Gasch (switch on the bending moment); default {default}")
    g.add_argument("--misalignment-offset-mm", type=float,
                   help="parallel offset of the coupling at the driven end (mm; with "
                   "--misalignment-angle-deg alone: 0)")
    g.add_argument("--misalignment-angle-deg", type=float,
                   help="angular misalignment of the coupling (deg; with "
                   "--misalignment-offset-mm alone: 0)")
    g.add_argument("--coupling-node", type=int, action=FromLibrary, default_of=_SETTINGS
                   + "coupling_node", help="the shaft node of the coupling's rotor-side flex "
                   "plane (default {default})")
    g.add_argument("--drive-torque-nm", type=float, action=FromLibrary,
                   default_of=_SETTINGS + "drive_torque_n_m",
                   help="the coupling's drive torque (N m, default {default})")
    g.add_argument("--spacer-length-mm", type=float, action=FromLibrary,
                   default_of=_SETTINGS + "spacer_length_m", convert=lambda m: m * 1e3,
                   help="the coupling's spacer length (mm, default {default})")
    g.add_argument("--loose-bearing", type=int,
                   help="the bearing (0-based) whose pedestal is loose on its seat (the rig "
                   "file must give that bearing a [bearings.pedestal])")
    g.add_argument("--loose-preload-n", type=float, default=0.0,
                   help="the dead load on the seat beyond the static load (N, default 0: "
                   "--gravity-m-s2 carries the weight)")
    g.add_argument("--loose-stiffness-n-m", type=float, action=FromLibrary,
                   default_of="rubdiag.simulation._faults:Looseness.loose_stiffness_n_m",
                   help="a retaining spring once the pedestal lifts (N/m, default {default})")
    g.add_argument("--loose-direction", metavar="AXIS", action=FromLibrary,
                   default_of="rubdiag.simulation._faults:Looseness.direction",
                   choices_of="rubdiag.simulation._faults:DIRECTIONS",
                   help="the direction the pedestal lifts off in, towards +: one of {choices} "
                   "(default {default}; z: across gravity along y, which then does not press "
                   "it on its seat)")


def run_options(args) -> dict:
    """The Run fields the fault options give: ``static_load`` and ``faults`` (only those
    asked for)."""
    from rubdiag.simulation import Crack, Faults, Looseness, Misalignment, StaticLoad

    out = {}
    if args.gravity_m_s2 is not None:
        out["static_load"] = StaticLoad(direction="y", gravity_m_s2=args.gravity_m_s2)
    faults = {}
    if args.crack_element is not None:
        faults["crack"] = Crack(element=args.crack_element, depth_ratio=args.crack_depth,
                                law=args.crack_law)
    if args.misalignment_offset_mm is not None or args.misalignment_angle_deg is not None:
        faults["misalignment"] = Misalignment(
            node=args.coupling_node, drive_torque_n_m=args.drive_torque_nm,
            spacer_length_m=args.spacer_length_mm * 1e-3,
            offset_m=(args.misalignment_offset_mm or 0.0) * 1e-3,
            angle_rad=math.radians(args.misalignment_angle_deg or 0.0))
    if args.loose_bearing is not None:
        faults["looseness"] = Looseness(bearing=args.loose_bearing,
                                        preload_n=args.loose_preload_n,
                                        loose_stiffness_n_m=args.loose_stiffness_n_m,
                                        direction=args.loose_direction)
    if faults:
        out["faults"] = Faults(**faults)
    return out
