"""A run on journal bearings: the films as elements, and the static state they carry.

A rig's plain journal bearings (``Bearing(journal=JournalFilm(...))``) have no springs in K:
in a run each is a :class:`~rubdiag.simulation._journal.JournalBearing` element between its
shaft node and the ground (or its pedestal), whose nonlinear film carries the rotor. The run
starts from the static equilibrium under its static load, ``K x = f + Bᵀ p(B x)`` with p
the films' forces at rest relative to the housing (turning at the run's speed): Newton's
method from the linearised guess — every journal where :func:`rubdiag._fluidfilm.
linearised_coefficients` puts it for its stated load, the rest from ``(K + K_b) x = f +
K_b x_journal`` — until a Newton step is below :data:`STATIC_RTOL` of the largest
displacement (the method converges quadratically: the residual is then round-off).
"""

from __future__ import annotations

import numpy as np

from rubdiag.simulation._journal import JournalBearing

__all__ = ["STATIC_RTOL", "equilibrium", "film_elements", "film_equilibrium", "journal_guess"]

#: the last Newton step's bound, relative to the largest static displacement
STATIC_RTOL = 1e-8
_ITERATIONS = 50


def film_elements(rig, dofs) -> tuple[JournalBearing, ...]:
    """The rig's journal bearings as elements, in ``Rig.bearings`` order (physical DOFs of
    the DOF map ``dofs``)."""
    out = []
    for k, b in enumerate(rig.bearings):
        if b.journal is None:
            continue
        film = b.journal
        journal = (dofs.index(b.node, "y"), dofs.index(b.node, "z"))
        housing = ((-1, -1) if b.pedestal is None else
                   (dofs.index(f"pedestal {k}", "y"), dofs.index(f"pedestal {k}", "z")))
        out.append(JournalBearing(dof_a=journal, dof_b=housing, mu_pa_s=film.viscosity_pa_s,
                                  radius_m=film.radius_m, length_m=film.length_m,
                                  clearance_m=film.clearance_m))
    return tuple(out)


def _film_forces(films, x: np.ndarray, speed: float, n: int):
    """The films' forces on the structure at rest (``Bᵀ p``, n) and their stiffness
    ``Bᵀ (∂p/∂x) B`` (dense n×n) at the state x."""
    from rubdiag._fluidfilm import film_force

    force, jac = np.zeros(n), np.zeros((n, n))
    out = np.zeros((2, 5))
    for film in films:
        a, b = np.asarray(film.dof_a), np.asarray(film.dof_b)
        rel = x[a] - np.where(b >= 0, x[np.maximum(b, 0)], 0.0)
        film_force(rel[0], rel[1], 0.0, 0.0, speed, film.mu_pa_s, film.radius_m,
                   film.length_m, film.clearance_m, out)
        for dofs, sign in ((a, 1.0), (b, -1.0)):
            if dofs[0] < 0:
                continue
            force[dofs] += sign * out[:, 0]
            for other, sign2 in ((a, 1.0), (b, -1.0)):
                if other[0] >= 0:
                    jac[np.ix_(dofs, other)] += sign * sign2 * out[:, 1:3]
    return force, jac


def film_equilibrium(model, f_static: np.ndarray, speed: float) -> np.ndarray:
    """The static state (n,) of ``model`` on its journal bearings under ``f_static`` at the
    spin speed ``speed`` (rad/s): module docstring. A ValueError when Newton's method does
    not converge."""
    Kb, _ = model.bearing_matrices(speed)
    return equilibrium(model.K.toarray(), Kb.toarray(), f_static,
                       film_elements(model.rig, model.dofs), journal_guess(model, speed),
                       speed)


def journal_guess(model, speed: float) -> np.ndarray:
    """A state (n,) with each journal where :func:`rubdiag._fluidfilm.linearised_coefficients`
    puts it for its bearing's stated load at ``speed`` (rad/s), zero elsewhere."""
    from rubdiag._fluidfilm import linearised_coefficients

    guess = np.zeros(model.n_dof)
    for k in model.journal_bearings:
        b = model.rig.bearings[k]
        f = b.journal
        _, _, position = linearised_coefficients(f.load_n, speed, f.viscosity_pa_s,
                                                 f.radius_m, f.length_m, f.clearance_m,
                                                 f.load_vector)
        guess[[model.dofs.index(b.node, "y"), model.dofs.index(b.node, "z")]] = position
    return guess


def equilibrium(K: np.ndarray, Kb: np.ndarray, f: np.ndarray, films, guess: np.ndarray,
                speed: float) -> np.ndarray:
    """The static state x of ``K x = f + Bᵀ p(B x)`` for the film elements ``films`` (in the
    coordinates of the dense K), from the linearised guess ``(K + Kb) x = f + Kb guess``
    (``Kb`` the films' stiffness there): module docstring."""
    n = K.shape[0]
    x = np.linalg.solve(K + Kb, f + Kb @ guess)
    for _ in range(_ITERATIONS):
        p, J = _film_forces(films, x, speed, n)
        step = np.linalg.solve(K - J, f + p - K @ x)
        x = x + step
        if np.abs(step).max() <= STATIC_RTOL * np.abs(x).max():
            return x
    raise ValueError(f"the static state on the journal bearings did not converge at "
                     f"{speed:g} rad/s (last Newton step {np.abs(step).max():.3g} m): the "
                     "films may not carry the static load at this speed")
