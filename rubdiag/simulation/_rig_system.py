"""A run's linear system as the integrator sees it: the seam between full and reduced model.

:func:`rig_system` turns a :class:`~rubdiag.simulation._run.Run` into a :class:`RigSystem` —
M, C, K and the unit-speed gyroscopic G, the unbalance load, the contact elements in the
system's coordinates, the linear steady state to start from, and how to recover physical
DOFs. The full model gives the sparse 412-DOF matrices and identity recovery; the reduced
model (``run.reduction``) gives dense Craig–Bampton matrices whose first coordinates are the
contact DOFs, so the contact elements are the same elements, renumbered. Everything else —
the gap ramp, the integrator, the result — is shared.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from rubdiag.simulation._elements import AnnularContact, PointContact
from rubdiag.simulation._films import film_elements, film_equilibrium
from rubdiag.simulation._idle_contacts import MIN_IDLE_GAP_M, is_idle
from rubdiag.simulation._loads import HarmonicForce
from rubdiag.simulation._run import Run

__all__ = ["RigSystem", "linear_approach", "rig_system"]


@dataclass(frozen=True)
class RigSystem:
    """``M x'' + (C + Ω G) x' + K x = f(t) + contact forces`` in the coordinates x.

    ``M``, ``C``, ``K``, ``G``: sparse (full model) or dense (reduced); ``force``: the
    unbalance at speed Ω, and the run's static load as order-0 terms; ``contacts``: the
    contact elements (a :class:`~rubdiag.simulation.PointContact` per blade, then an
    :class:`~rubdiag.simulation.AnnularContact` per stator), in x's numbering; ``x0``,
    ``v0``: the linear steady state at t = 0 (the static deflection ``K⁻¹ f_static`` plus
    the harmonic steady state); ``approach``: the largest radial approach of that state at
    the contacts (m); ``recovery``: None (x is q) or T with ``q = T x``; ``linear_solver``:
    what the integrator uses ("sparse" or "dense"); ``model``: "full" or "reduced";
    ``extra``: diagnostics of the reduction; ``fault_elements``: the run's fault elements
    (a breathing crack, a loose pedestal), then its journal bearings' films
    (:mod:`rubdiag.simulation._films`), in x's numbering; the misaligned coupling's loads
    are in ``force``; ``K`` is without the springs a fault element takes over (a loose
    pedestal's support in its direction); ``gap_shift`` (one per contact): what each
    contact's gap was raised by so that it is the run's gap at the static equilibrium (its
    static approach, m; zeros without a static load or with its clearances
    ``"unloaded"``), over which ``approach`` is measured; ``idle``: the blade contacts the
    run cannot close, left out of a reduced model (physical DOFs;
    :mod:`rubdiag.simulation._idle_contacts`), which the result reports open."""

    M: object
    C: object
    K: object
    G: object
    force: HarmonicForce
    contacts: tuple
    x0: np.ndarray
    v0: np.ndarray
    approach: float
    recovery: np.ndarray | None
    linear_solver: str
    model: str
    extra: dict
    fault_elements: tuple = ()
    gap_shift: np.ndarray | None = None
    idle: tuple = ()

    def damping(self, speed: float):
        """``C + Ω G`` at spin speed Ω (rad/s)."""
        D = self.C + speed * self.G
        return D.tocsr() if hasattr(D, "tocsr") else D


def rig_system(run: Run, model) -> RigSystem:
    """The linear system of ``run`` on the assembled (Rayleigh-damped) ``model``: full, or
    Craig–Bampton reduced when ``run.reduction`` is set."""
    speed = run.speed_rad_s
    F = model.unbalance_force(run.unbalance, speed)
    f_static = None if run.static_load is None else run.static_load.vector(model.M, model.dofs)
    x_static = q_static = None
    if run.reduction is None:
        from rubdiag.modal import harmonic_response

        q_hat = harmonic_response(model, speed, run.unbalance).amplitudes
        x_hat = q_hat
        loaded = np.flatnonzero(F)
        force = HarmonicForce(loaded, F[loaded], speed)
        if f_static is not None:
            x_static = q_static = _static_state(model, f_static, speed)
            force = force + _static_force(f_static, speed)
        contacts, approach, shift = _contacts(run, model, q_hat, q_static)
        idle = ()
        force = _with_fault_loads(force, run, model, speed, lambda dofs: dofs)
        fault_elements = () if run.faults is None else run.faults.elements(run.rig)
        fault_elements += film_elements(run.rig, model.dofs)
        parts = (model.M, model.C, model.K, model.G)
        recovery, solver, extra = None, "sparse", {}
    else:
        reduced = _Reduced(run, model, F, f_static, blade_contacts=not _may_idle(run, model))
        if not reduced.blade_contacts and not is_idle(run.gap_m, reduced.approach):
            reduced = _Reduced(run, model, F, f_static, blade_contacts=True)
        x_hat, x_static, q_hat, q_static = (reduced.x_hat, reduced.x_static, reduced.q_hat,
                                            reduced.q_static)
        force, contacts, approach, shift = (reduced.force, reduced.contacts, reduced.approach,
                                            reduced.shift)
        idle, index = reduced.idle, reduced.index
        fault_elements = () if run.faults is None else tuple(
            _renumbered(e, index) for e in run.faults.elements(run.rig))
        fault_elements += reduced.films
        model_r = reduced.model
        parts = (model_r.M, model_r.C, model_r.K, model_r.G)
        recovery, solver = model_r.basis.T, "dense"
        extra = {"n_reduced": model_r.n_reduced, "cutoff_hz": run.reduction.cutoff_hz,
                 "reduction_seconds": model_r.build_seconds}
    if run.faults is not None:
        parts = (*parts[:2], _without_taken_springs(parts[2], run, model,
                                                    None if recovery is None else index),
                 parts[3])
    x0 = np.real(x_hat) if x_static is None else np.real(x_hat) + x_static
    if model.journal_bearings:
        _check_start_in_clearance(run, model, q_hat, q_static)
    return RigSystem(*parts, force=force, contacts=contacts, x0=x0,
                     v0=np.real(1j * speed * x_hat), approach=approach, recovery=recovery,
                     linear_solver=solver, model="full" if recovery is None else "reduced",
                     extra=extra, fault_elements=fault_elements, gap_shift=shift, idle=idle)


def _may_idle(run: Run, model) -> bool:
    """Whether the run's blade contacts may be left out (:mod:`.idle_contacts`): a reduced
    run whose gap is at least the idle minimum, unless the reduction keeps them, and whose
    rig has other nonlinear elements (without, the run is linear: no reduced model)."""
    from rubdiag.reduce import boundary_dofs

    return (run.contact_law is not None and not run.reduction.keep_idle_contacts
            and run.gap_m >= MIN_IDLE_GAP_M
            and boundary_dofs(model, _with_fault_nodes(run), blade_contacts=False).size > 0)


class _Reduced:
    """The reduced parts of a run's system: its reduced model (with or without the blade
    contacts' DOFs), its steady state, loads and contacts in the reduced coordinates, and
    the blade contacts left out (``idle``, physical DOFs; empty with them)."""

    def __init__(self, run: Run, model, F, f_static, blade_contacts: bool):
        from rubdiag.reduce import reduced_model

        speed = run.speed_rad_s
        spec = dataclasses.replace(_with_fault_nodes(run), keep_idle_contacts=False)
        self.blade_contacts = blade_contacts
        self.model = reduced = reduced_model(run.rig, spec, blade_contacts=blade_contacts)
        self.index = index = reduced.basis.boundary_index
        self.films = tuple(_renumbered(e, index) for e in film_elements(run.rig, model.dofs))
        self.x_hat = _reduced_response(reduced, model, F, speed)
        self.q_hat = reduced.basis.T @ self.x_hat
        F_r = reduced.project_force(F)
        force = HarmonicForce(np.arange(F_r.size), F_r, speed)
        self.x_static = self.q_static = None
        if f_static is not None:    # the reduced system's own static equilibrium
            f_r = reduced.project_force(f_static)
            self.x_static = (_reduced_equilibrium(reduced, model, f_r, self.films, speed)
                             if self.films else np.linalg.solve(reduced.K, f_r))
            self.q_static = reduced.basis.T @ self.x_static
            force = force + _static_force(f_r, speed)
        contacts, self.approach, shift = _contacts(run, model, self.q_hat, self.q_static)
        n_blade = 0 if blade_contacts or run.contact_law is None else len(run.contact_law.blades)
        self.shift = shift[n_blade:]
        self.idle = contacts[:n_blade]
        self.contacts = tuple(_renumbered(c, index) for c in contacts[n_blade:])
        # the fault nodes are boundary coordinates: a load there is a load on its coordinate
        self.force = _with_fault_loads(force, run, model, speed, index)


def linear_approach(run: Run, model, of: str | None = None) -> float:
    """``rig_system(run, model).approach`` of the full model, computing only what it
    depends on: the harmonic response at the run's speed, and the static state only where
    the approach includes it (clearances ``"unloaded"``, stator contacts). The run's start
    is not checked here (:func:`rig_system` does that). ``of``: ``"blades"`` or ``"seals"``
    for the approach at those contacts only (None: every contact's)."""
    from rubdiag.modal import harmonic_response

    speed = run.speed_rad_s
    q_hat = harmonic_response(model, speed, run.unbalance).amplitudes
    load = run.static_load
    q_static = None
    if load is not None and (load.clearances != "loaded" or run.rig.stator_contacts):
        q_static = _static_state(model, load.vector(model.M, model.dofs), speed)
    return _contacts(run, model, q_hat, q_static, of)[1]


def _static_state(model, f_static: np.ndarray, speed: float) -> np.ndarray:
    """The full model's static state under ``f_static`` (m): on journal bearings the films'
    equilibrium at ``speed`` (rad/s), else ``K⁻¹ f``."""
    if model.journal_bearings:
        return film_equilibrium(model, f_static, speed)
    return _static_deflection(model.K, f_static)


def _check_start_in_clearance(run: Run, model, q_hat, q_static) -> None:
    """A run starts on its linear steady orbit: every journal must stay inside its clearance
    on it (the short-bearing force has no meaning beyond), or the run is refused by name —
    the films cannot carry that unbalance at that speed. The bound is the static offset plus
    the harmonic amplitude ``√(|ŷ|² + |ẑ|²)`` (the orbit's semi-major axis or more)."""
    for k in model.journal_bearings:
        b = model.rig.bearings[k]
        journal = [model.dofs.index(b.node, d) for d in ("y", "z")]
        housing = ([model.dofs.index(f"pedestal {k}", d) for d in ("y", "z")]
                   if b.pedestal is not None else None)
        amplitude = q_hat[journal] - (0.0 if housing is None else q_hat[housing])
        offset = q_static[journal] - (0.0 if housing is None else q_static[housing])
        reach = np.hypot(*offset) + np.sqrt(np.sum(np.abs(amplitude) ** 2))
        clearance = b.journal.clearance_m
        if reach >= clearance:
            raise ValueError(f"the linear start puts journal bearing {k} (shaft node {b.node}) "
                             f"{reach / clearance:.3g} clearances from its centre at "
                             f"{run.speed_rpm:.6g} rpm (allowed: inside its clearance, < 1): "
                             "its film cannot carry this unbalance at this speed")


def _reduced_films(reduced, model, speed: float):
    """The journal bearings' linearised films in the reduced coordinates (dense): their DOFs
    are boundary coordinates, whose rows of T are unit rows, so ``Tᵀ K_b T`` is exact."""
    Kb, Cb = model.bearing_matrices(speed)
    T = reduced.basis.T
    return T.T @ (Kb @ T), T.T @ (Cb @ T)


def _reduced_response(reduced, model, F, speed: float) -> np.ndarray:
    """The reduced steady response to the unbalance F̂, the films linearised at ``speed``."""
    if not model.journal_bearings:
        return reduced.harmonic_response(F, speed)
    Kb, Cb = _reduced_films(reduced, model, speed)
    Z = (reduced.K + Kb - speed**2 * reduced.M
         + 1j * speed * (reduced.C + Cb + speed * reduced.G))
    return np.linalg.solve(Z, reduced.project_force(F))


def _reduced_equilibrium(reduced, model, f_r, films, speed: float) -> np.ndarray:
    """The reduced static state the films carry (:func:`rubdiag.simulation._films.equilibrium`
    in the reduced coordinates)."""
    from rubdiag.simulation._films import equilibrium, journal_guess

    Kb, _ = _reduced_films(reduced, model, speed)
    boundary = reduced.basis.boundary          # reduced coordinate k < n_b is boundary[k]
    guess_r = np.zeros(reduced.K.shape[0])
    guess_r[: boundary.size] = journal_guess(model, speed)[boundary]
    return equilibrium(np.asarray(reduced.K), Kb, f_r, films, guess_r, speed)


def _renumbered(element, index):
    """An element with its physical DOFs renumbered to the reduced coordinates."""
    if hasattr(element, "dof_a"):               # a contact, a film (-1 stays ground)
        return dataclasses.replace(element,
                                   dof_a=tuple(int(i) for i in index(element.dof_a)),
                                   dof_b=tuple(int(i) for i in index(element.dof_b)))
    if hasattr(element, "element_dofs"):        # a breathing crack
        return dataclasses.replace(
            element, element_dofs=tuple(int(i) for i in index(element.element_dofs)))
    base = element.base_dof                     # a loose pedestal
    return dataclasses.replace(element, dof=int(index([element.dof])[0]),
                               base_dof=-1 if base < 0 else int(index([base])[0]))


def _without_taken_springs(K, run: Run, model, index):
    """``K`` without the springs to ground the run's fault elements take over (a loose
    pedestal's support: the element is its seat). The steady state the run starts from is
    that of the seated, linear model, where the element's force equals the spring's.

    The DOF is physical in the reduced model too (a boundary coordinate of the
    Craig–Bampton basis, whose row of T is a unit row), so the spring is the same diagonal
    term there: removing it is exact. A new matrix: the cached model is shared."""
    taken = run.faults.removed_stiffness(run.rig, model.dofs)
    if not taken:
        return K
    dofs = np.array([d for d, _ in taken], dtype=np.int64)
    k = np.array([v for _, v in taken])
    if index is not None:
        dofs = np.asarray(index(dofs), dtype=np.int64)
    if hasattr(K, "tocsr"):
        import scipy.sparse as sp

        return (K - sp.csr_matrix((k, (dofs, dofs)), shape=K.shape)).tocsr()
    K = np.array(K, copy=True)
    K[dofs, dofs] -= k
    return K


def _static_deflection(K, f: np.ndarray) -> np.ndarray:
    """``K⁻¹ f`` of the sparse full model (m)."""
    import scipy.sparse.linalg as spla

    return spla.spsolve(K.tocsc(), f)


def _static_force(f: np.ndarray, speed: float) -> HarmonicForce:
    """The static load ``f`` (n,) as order-0 "constant" terms on its nonzero DOFs."""
    loaded = np.flatnonzero(f)
    return HarmonicForce(loaded, f[loaded], speed, order=0.0, law="constant")


def _with_fault_nodes(run: Run):
    """The run's reduction, keeping its faults' shaft nodes physical too."""
    if run.faults is None:
        return run.reduction
    nodes = set(run.reduction.shaft_nodes) | set(run.faults.shaft_nodes(run.rig))
    if run.faults.misalignment is not None:
        nodes.add(run.faults.misalignment.node)
    return dataclasses.replace(run.reduction, shaft_nodes=tuple(sorted(nodes)))


def _with_fault_loads(force: HarmonicForce, run: Run, model, speed: float,
                      index) -> HarmonicForce:
    """``force`` and the misaligned coupling's loads, their DOFs through ``index`` (the
    same ``force`` without one)."""
    if run.faults is None or run.faults.misalignment is None:
        return force
    loads = run.faults.misalignment.forces(model, speed)
    return force + dataclasses.replace(loads, dofs=np.asarray(index(loads.dofs),
                                                              dtype=np.int64))


def _contacts(run: Run, model, linear, static=None,
              of: str | None = None) -> tuple[tuple, float, np.ndarray]:
    """Contact elements of the run (physical DOFs; the blades', then the stators'), the
    largest radial approach of the linear response ``linear`` (complex amplitudes of every
    DOF) at them (m; ``of`` "blades" or "seals": at those only), and each contact's gap
    shift (m). With a static deflection ``static`` (real, every DOF; None: none) and
    clearances "loaded", each blade contact's gap is raised by its static approach (its
    shift), each stator is centred on the static state, and the approach is the harmonic's
    alone; with "unloaded", the approach is an upper bound, |static| + the harmonic's
    largest excursion."""
    if of not in (None, "blades", "seals"):
        raise ValueError(f"of = {of!r} (allowed: None, 'blades', 'seals')")
    contacts = ()
    start = 0.0
    shifts = []
    loaded = static is not None and run.static_load.clearances == "loaded"
    law = run.contact_law
    if law is not None:
        geo = model.blade_contacts
        if law.blades != run.rig.contact.blades:
            raise ValueError("contact.blades must equal the rig's contact blades (the "
                             "contact geometry belongs to the rig)")
        n = len(law.blades)
        rel = linear[geo.tip_dofs] - linear[geo.casing_dofs]          # (n, 2) complex
        approach = np.abs(np.sum(rel * geo.normal, axis=1))
        shift = np.zeros(n)
        if static is not None:
            sag = np.sum((static[geo.tip_dofs] - static[geo.casing_dofs]) * geo.normal, axis=1)
            if loaded:      # the gap is the clearance at the static state (g = g0 - x)
                shift = sag
            else:
                approach = approach + np.abs(sag)
        gaps = np.full(n, run.gap_m) + shift
        contacts = tuple(
            PointContact(dof_a=tuple(geo.tip_dofs[i].tolist()),
                         dof_b=tuple(geo.casing_dofs[i].tolist()),
                         normal=tuple(geo.normal[i].tolist()),
                         tangent=tuple(geo.tangent[i].tolist()), gap=float(gaps[i]),
                         k_n=law.normal_stiffness_n_m, k_t=law.tangential_stiffness_n_m,
                         mu=law.friction_coefficient, augmented=law.augmented,
                         eps=law.penetration_tolerance_m)
            for i in range(n))
        start = float(approach.max()) if of != "seals" else 0.0
        shifts.append(shift)
    for sc in run.rig.stator_contacts:
        shifts.append(np.zeros(1))
        dofs = [model.dofs.index(sc.node, "y"), model.dofs.index(sc.node, "z")]
        radius = sc.shaft_radius_m
        if radius is None:
            shaft = run.rig.shaft
            i = min(sc.node - shaft.first_node, shaft.n_elements - 1)
            radius = 0.5 * shaft.outer_diameters_m[i]
        # "loaded": the stator is aligned on the loaded rotor, centred on its static state
        centre = static[dofs] if loaded else np.zeros(2)
        clearance = sc.clearance_m if run.seal_clearance_m is None else run.seal_clearance_m
        contacts += (AnnularContact(dof_a=tuple(dofs), clearance=clearance, radius=radius,
                                    k_n=sc.stiffness_n_m, mu=sc.friction_coefficient,
                                    centre=tuple(centre.tolist())),)
        a, b = linear[dofs[0]], linear[dofs[1]]
        orbit = np.sqrt(0.5 * (abs(a) ** 2 + abs(b) ** 2 + abs(a * a + b * b)))
        if static is not None and not loaded:
            orbit = orbit + np.hypot(static[dofs[0]], static[dofs[1]])
        if of != "blades":
            start = max(start, float(orbit))
    return contacts, start, np.concatenate(shifts) if shifts else np.zeros(0)
