"""How far a reduced model is from the full one: :func:`check`.

Four comparisons against the full model, each up to the reduction's cutoff (the band the
model answers for is the cutoff over the margin, ``Reduction.band_hz``: 1 kHz by default,
which holds every order up to 8× at 6840 rpm):

* **natural frequencies** — the undamped modes (gyroscopic terms kept) at each speed;
* **critical speeds** — the forward rotor critical speeds (synchronous solutions whose
  shapes, recovered to physical DOFs, whirl forwards with most energy in the shaft);
* **contact compliance** — ``H(ω) = B Z(ω)⁻¹ Bᵀ`` between the local contact coordinates
  (normal, tangential relative displacement of the 2 n_c contact directions), with
  ``Z(ω) = K − ω² M + iω (C + Ω G)``: static (ω = 0; exact for Craig–Bampton, whose
  constraint modes span every static boundary load) and dynamic;
* **frequency responses** — from the contact forces and the unbalance DOFs to the contact
  coordinates and the DOFs of ``rubdiag.simulation.default_sensors`` (bearings, disc,
  casing).

Errors of the matrices are relative Frobenius norms, ``‖H_r − H‖ / ‖H‖``, per frequency.
The tolerance on frequencies and critical speeds in the band is :data:`FREQUENCY_TOLERANCE`
(0.5 %). Between the band and the cutoff the errors are reported, not held to it: on the
paper rig the contact blades' first bending (1042 Hz) comes out 1.5 % high, as the Rayleigh
quotient of a cantilever's static tip-load shape does (its free tip is a boundary DOF, and
its clamped-pinned modes lie above 4.5 kHz).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rubdiag._tolerances import REAL_ROOT
from rubdiag.reduce._reduced import ReducedModel, reduced_model
from rubdiag.reduce._spec import Reduction

if TYPE_CHECKING:   # loaded by check() only: a reduced run does not need pandas (0.4 s)
    import pandas as pd

__all__ = ["FREQUENCY_TOLERANCE", "RESPONSE_TOLERANCE", "STATIC_TOLERANCE", "ReductionCheck",
           "check"]

#: Largest relative error allowed on natural frequencies and critical speeds in the band
FREQUENCY_TOLERANCE = 0.005
#: ... on the dynamic compliance and the frequency responses in the band (Frobenius norm)
RESPONSE_TOLERANCE = 0.05
#: ... on the static compliance at the contacts (Craig–Bampton: exact up to round-off)
STATIC_TOLERANCE = 1e-8


@dataclass(frozen=True)
class ReductionCheck:
    """The comparisons of :func:`check`, as tables (frequencies in Hz, speeds in rpm).

    ``frequencies``: speed_rpm, mode, full_hz, reduced_hz, error, in_band;
    ``critical_speeds``: critical, full_rpm, reduced_rpm, error, in_band; ``compliance``:
    speed_rpm, frequency_hz, error (frequency 0 is the static flexibility); ``responses``:
    speed_rpm, frequency_hz, contact_error, sensor_error. ``n_reduced`` / ``n_full``
    coordinates, ``cutoff_hz`` and ``band_hz``.

    Parameters
    ----------
    cutoff_hz : float
        The reduction's cutoff (Hz).
    band_hz : float
        The frequency band compared (Hz).
    n_full, n_reduced : int
        Coordinates of the full and the reduced model.
    frequencies, critical_speeds, compliance, responses : pandas.DataFrame
        The tables above.
    """

    cutoff_hz: float
    band_hz: float
    n_full: int
    n_reduced: int
    frequencies: pd.DataFrame
    critical_speeds: pd.DataFrame
    compliance: pd.DataFrame
    responses: pd.DataFrame

    @property
    def passed(self) -> bool:
        """Every natural frequency and critical speed in the band within 0.5 %, the
        responses in the band within 5 %, the static compliance exact to 1e-8."""
        s = self.summary_errors()
        return (s["max_frequency_error_in_band"] <= FREQUENCY_TOLERANCE
                and s["max_critical_speed_error_in_band"] <= FREQUENCY_TOLERANCE
                and s["static_compliance_error"] <= STATIC_TOLERANCE
                and all(s[f"max_{k}_error_in_band"] <= RESPONSE_TOLERANCE for k in (
                    "dynamic_compliance", "contact_response", "sensor_response")))

    def summary(self) -> dict:
        """Sizes, the largest errors (relative) and the verdict."""
        return {"n_full": self.n_full, "n_reduced": self.n_reduced,
                "cutoff_hz": self.cutoff_hz, "band_hz": self.band_hz,
                "n_modes_compared": len(self.frequencies), **self.summary_errors(),
                "passed": self.passed}

    def summary_errors(self) -> dict:
        """The largest relative errors, in the band and up to the cutoff."""
        static = self.compliance.frequency_hz == 0
        return {
            "max_frequency_error_in_band": _max(self.frequencies, True),
            "max_frequency_error_to_cutoff": _max(self.frequencies, False),
            "max_critical_speed_error_in_band": _max(self.critical_speeds, True),
            "max_critical_speed_error_to_cutoff": _max(self.critical_speeds, False),
            "static_compliance_error": float(self.compliance.error[static].max()),
            **_band_and_cutoff("dynamic_compliance_error", self.compliance[~static], "error",
                               self.band_hz),
            **_band_and_cutoff("contact_response_error", self.responses, "contact_error",
                               self.band_hz),
            **_band_and_cutoff("sensor_response_error", self.responses, "sensor_error",
                               self.band_hz),
        }


def check(rig, reduction: Reduction | None = None, speeds_rpm=None,
          n_frequencies: int = 120) -> ReductionCheck:
    """Compare the reduced model of ``rig`` with the full model (module docstring).

    At each spin speed: the natural frequencies below the cutoff, the contact compliance
    (static and on the frequency grid) and the frequency responses; once: the forward
    critical speeds below the cutoff.

    Parameters
    ----------
    rig : Rig
        The rig, with at least one nonlinear element (as :func:`reduced_model` needs);
        the compliance is taken between its blade contacts.
    reduction : Reduction or None
        The reduction to check; None: ``Reduction()`` (as :func:`reduced_model`).
    speeds_rpm : sequence of float or None
        Spin speeds of the comparison (rpm); None: 0 and the rig's first two forward
        critical speeds (the study's running speeds).
    n_frequencies : int
        Points of the frequency grid of the compliance and the responses, log-spaced from
        1 Hz to the cutoff.

    Returns
    -------
    ReductionCheck
        The four comparison tables; ``.passed`` is the verdict (in the band: frequencies
        and critical speeds within 0.5 %, responses within 5 %; the static compliance to
        1e-8), ``.summary()`` the largest errors.

    See Also
    --------
    reduced_model : The reduced model compared.
    Reduction : What a reduction keeps.
    """
    import pandas as pd

    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds, with_rayleigh

    reduced = reduced_model(rig, reduction)
    model = with_rayleigh(assemble(rig))
    cutoff = reduced.reduction.cutoff_hz
    band = reduced.reduction.band_hz
    full_crit = critical_speeds(model, n=8) * 30.0 / np.pi
    full_crit = full_crit[full_crit / 60.0 < cutoff]
    if speeds_rpm is None:
        speeds_rpm = (0.0, *full_crit[:2].tolist())
    speeds = np.asarray(speeds_rpm, dtype=float) * np.pi / 30.0
    freqs = np.geomspace(1.0, cutoff, n_frequencies)
    B = _contact_matrix(model)
    sensors = _sensor_dofs(model)
    loads = np.flatnonzero(model.unbalance_force(rig.unbalance(1), 1.0))
    rows_f, rows_c, rows_r = [], [], []
    for speed in speeds:
        rpm = speed * 30.0 / np.pi
        f_full = _natural_frequencies_hz(model.M, speed * model.G, model.K, cutoff)
        f_red = _natural_frequencies_hz(reduced.M, speed * reduced.G, reduced.K, cutoff)
        for k, (a, b) in enumerate(zip(f_full, f_red, strict=False)):
            rows_f.append((rpm, k + 1, a, b, b / a - 1.0, a < band))
        for f in (0.0, *freqs):
            H, H_r = _responses(model, reduced, speed, 2 * np.pi * f, B, sensors, loads)
            nc = B.shape[0]
            rows_c.append((rpm, f, _rel(H_r[:nc, :nc], H[:nc, :nc])))
            if f > 0:
                rows_r.append((rpm, f, _rel(H_r[:nc], H[:nc]), _rel(H_r[nc:], H[nc:])))
    red_crit = _reduced_critical_speeds_rpm(model, reduced)
    crit = [(k + 1, a, b, b / a - 1.0, a / 60.0 < band)
            for k, (a, b) in enumerate(zip(full_crit, red_crit, strict=False))]
    return ReductionCheck(
        cutoff_hz=cutoff, band_hz=band, n_full=model.n_dof, n_reduced=reduced.n_reduced,
        frequencies=pd.DataFrame(rows_f, columns=["speed_rpm", "mode", "full_hz",
                                                  "reduced_hz", "error", "in_band"]),
        critical_speeds=pd.DataFrame(crit, columns=["critical", "full_rpm", "reduced_rpm",
                                                    "error", "in_band"]),
        compliance=pd.DataFrame(rows_c, columns=["speed_rpm", "frequency_hz", "error"]),
        responses=pd.DataFrame(rows_r, columns=["speed_rpm", "frequency_hz", "contact_error",
                                                "sensor_error"]))


def _contact_matrix(model) -> np.ndarray:
    """B (2 n_c, n): the local normal and tangential relative displacement of every blade
    contact element."""
    geo = model.blade_contacts
    B = np.zeros((2 * len(geo.normal), model.n_dof))
    for e, (tip, casing) in enumerate(zip(geo.tip_dofs, geo.casing_dofs, strict=True)):
        for r, axis in enumerate((geo.normal[e], geo.tangent[e])):
            B[2 * e + r, tip] += axis
            B[2 * e + r, casing] -= axis
    return B


def _sensor_dofs(model) -> list[int]:
    """The DOFs of ``rubdiag.simulation.default_sensors``: y and z at the bearings and the
    bladed disc, y of the casing at contact element 1."""
    rig = model.rig
    disc = rig.blades.disc_node if rig.blades is not None else rig.discs[0].node
    nodes = sorted({b.node for b in rig.bearings} | {disc})
    dofs = [model.dofs.index(f"shaft {n}", d) for n in nodes for d in ("y", "z")]
    if rig.contact is not None and rig.casing is not None:
        dofs.append(model.dofs.index(f"casing {rig.contact_casing_node(1)}", "y"))
    return dofs


def _natural_frequencies_hz(M, D, K, below_hz: float) -> np.ndarray:
    """Undamped natural frequencies (Hz, with the skew D = Ω G) below ``below_hz``."""
    n = M.shape[0]
    if sp.issparse(M):   # the full model: shift-invert about the middle of the band
        A = sp.bmat([[None, sp.identity(n)], [-K, -D]], format="csc")
        Bm = sp.bmat([[sp.identity(n), None], [None, M]], format="csc")
        lam = spla.eigs(A, M=Bm, sigma=0.0, k=min(2 * n - 2, 160), v0=np.ones(2 * n),
                        return_eigenvectors=False)
    else:
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -D]])
        Bm = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
        lam = sla.eig(A, Bm, right=False)
    f = np.sort(np.abs(lam[lam.imag > 0].imag)) / (2 * np.pi)
    return f[f < below_hz]


def _responses(model, reduced: ReducedModel, speed, omega, B, sensors, loads):
    """H (full) and H_r (reduced): rows the contact coordinates then the sensors, columns
    the contact directions then the unbalance DOFs, at frequency ω (rad/s)."""
    inputs = np.hstack([B.T, np.eye(model.n_dof)[:, loads]])
    Z = (model.K - omega**2 * model.M
         + 1j * omega * (model.C + speed * model.G)).tocsc()
    X = spla.splu(Z).solve(inputs.astype(complex))
    T = reduced.basis.T
    Z_r = reduced.K - omega**2 * reduced.M + 1j * omega * (reduced.C + speed * reduced.G)
    X_r = T @ np.linalg.solve(Z_r, T.T @ inputs)
    return (np.vstack([B @ X, X[sensors]]), np.vstack([B @ X_r, X_r[sensors]]))


def _reduced_critical_speeds_rpm(model, reduced: ReducedModel) -> np.ndarray:
    """Forward rotor critical speeds of the reduced model (rpm): ``K x = Ω² (M − iG) x``,
    classified on the recovered physical shapes as the full model's are."""
    from rubdiag.modal._shapes import energy_shares, whirl_ratio

    lam, vec = sla.eig(reduced.K, reduced.M - 1j * reduced.G)
    ok = np.isfinite(lam) & (lam.real > 0) & (np.abs(lam.imag) < REAL_ROOT * np.abs(lam))
    lam, vec = lam[ok].real, vec[:, ok]
    order = np.argsort(lam)
    shapes = reduced.basis.T @ vec[:, order]
    forward = (whirl_ratio(model, shapes) > 0) & (
        energy_shares(model, shapes)["shaft_share"] >= 0.25)
    return np.sqrt(lam[order][forward]) * 30.0 / np.pi


def _band_and_cutoff(name: str, table: pd.DataFrame, column: str, band: float) -> dict:
    """The largest value of ``column`` in the band and up to the cutoff."""
    in_band = table[column][table.frequency_hz <= band]
    return {f"max_{name}_in_band": float(in_band.max()),
            f"max_{name}_to_cutoff": float(table[column].max())}


def _max(table: pd.DataFrame, in_band: bool) -> float:
    errors = table.error[table.in_band] if in_band else table.error
    return float(errors.abs().max()) if len(errors) else 0.0


def _rel(A: np.ndarray, ref: np.ndarray) -> float:
    return float(np.linalg.norm(A - ref) / np.linalg.norm(ref))
