"""Recording: the samples a run keeps, at exact step ends.

Every ``run.out_ticks`` ticks the recorded DOFs, each element's record and the energy
ledger (:func:`record`); every ``run.sen_ticks`` ticks (the base step) the sensor stream's
displacement, velocity and acceleration (:func:`record_sensors`), filled in within a step
longer than the base step by cubic Hermite interpolation (:func:`interpolate_sensors`).
Recorded values are the state at DOFs, or, for a reduced model, the physical DOFs recovered
by a map (:func:`recover`).
"""

from __future__ import annotations

from rubdiag._kernels.products import add_columns
from rubdiag._numba import njit

__all__ = ["interpolate_sensors", "record", "record_sensors", "recover"]


@njit(inline="always")
def recover(map_t, dofs, x, out):
    """Recorded values of the state ``x``: ``x[dofs]``, or ``mapᵀ x`` for a non-empty
    ``map_t`` (the physical DOFs of a reduced model).

    Inlined, and both paths run, each over a count that is 0 when it does not apply: as a
    call with an ``if`` over the arrays it made Numba count references in the records (12
    increfs in the sensors' record, which runs at every step of a sensor stream: 0.15-0.25
    µs per step).

    Parameters
    ----------
    map_t : ndarray (n, n_out)
        The recovery map, or empty (0, 0).
    dofs : ndarray (n_out) int
        The DOFs read when there is no map.
    x : ndarray (n)
        The state (m, m/s or m/s²).
    out : ndarray (n_out)
        The recorded values, overwritten.
    """
    mapped = map_t.shape[0] > 0
    n_gather = 0 if mapped else dofs.shape[0]
    for r in range(n_gather):
        out[r] = x[dofs[r]]
    n_out = out.shape[0] if mapped else 0
    for i in range(n_out):
        out[i] = 0.0
    add_columns(map_t, x, 0, map_t.shape[0] if n_out > 0 else 0, 0, n_out, out)


@njit
def record(index, q, v, momentum, elastic_force, record_dofs, record_map, track, progress,
           recorded_q, recorded_elements, recorded_energy):
    """Record sample ``index``.

    The recorded DOFs (their largest magnitude is the scale of the long steps' error
    tolerance until the next sample), each element's record, and the energy ledger with the
    kinetic and strain energies ``vᵀ M v / 2``, ``qᵀ K q / 2``.

    Parameters
    ----------
    index : int
        The sample.
    q, v : ndarray (n)
        Displacement (m) and velocity (m/s).
    momentum, elastic_force : ndarray (n)
        M v (N s) and K q (N).
    record_dofs, record_map : ndarray
        The recorded DOFs (:func:`recover`).
    track : ndarray (n_e) records.TRACK
        Each element's committed record.
    progress : ndarray (1) records.PROGRESS
        The ledger (J); its ``scale`` (m) is set.
    recorded_q : ndarray (n_out, n_rec)
        The recorded displacements (m).
    recorded_elements : ndarray (n_out, n_e) records.SAMPLE
        Each element's record per sample.
    recorded_energy : ndarray (n_out) records.ENERGY
        The ledger per sample (J).
    """
    recover(record_map, record_dofs, q, recorded_q[index])
    scale = 0.0
    for r in range(recorded_q.shape[1]):
        scale = max(scale, abs(recorded_q[index, r]))
    progress[0].scale = scale
    for e in range(track.shape[0]):
        k = track[e]
        o = recorded_elements[index, e]
        o.fn = k.fn
        o.ft = k.ft
        o.status = k.status
        o.gap = k.gap
        o.slip = k.slip
    v_m_v = 0.0
    q_k_q = 0.0
    for i in range(q.shape[0]):
        v_m_v += v[i] * momentum[i]
        q_k_q += q[i] * elastic_force[i]
    pr = progress[0]
    en = recorded_energy[index]
    en.w_ext = pr.w_ext
    en.w_drive = pr.w_drive
    en.d_visc = pr.d_visc
    en.d_fric = pr.d_fric
    en.d_num = pr.d_num
    en.kinetic = 0.5 * v_m_v
    en.strain = 0.5 * q_k_q
    en.contact = pr.e_contact


@njit
def record_sensors(index, q, v, a, sensor_dofs, sensor_map, sensor_q, sensor_v, sensor_a):
    """Record sensor sample ``index``: displacement, velocity and acceleration.

    Parameters
    ----------
    index : int
        The sample.
    q, v, a : ndarray (n)
        The state (m, m/s, m/s²).
    sensor_dofs, sensor_map : ndarray
        The sensors' DOFs (:func:`recover`).
    sensor_q, sensor_v, sensor_a : ndarray (n_sen_out, n_s)
        The sensor stream.
    """
    recover(sensor_map, sensor_dofs, q, sensor_q[index])
    recover(sensor_map, sensor_dofs, v, sensor_v[index])
    recover(sensor_map, sensor_dofs, a, sensor_a[index])


@njit(error_model="numpy")
def interpolate_sensors(i0, i1, h, sensor_q, sensor_v, sensor_a):
    """The sensor samples strictly between ``i0`` and ``i1``, the ends of a long step (both
    recorded).

    Cubic Hermite in displacement (from q and v at the ends) and in velocity (from v and
    a), linear in acceleration — the base step's stream, whose anti-alias filter then sees
    the same rate wherever the step is.

    Parameters
    ----------
    i0, i1 : int
        The samples at the step's ends.
    h : float
        The step (s).
    sensor_q, sensor_v, sensor_a : ndarray (n_sen_out, n_s)
        The sensor stream (m, m/s, m/s²), filled in.
    """
    n = i1 - i0
    for k in range(1, n):
        s = k / n
        s2 = s * s
        s3 = s2 * s
        h00 = 2.0 * s3 - 3.0 * s2 + 1.0
        h10 = (s3 - 2.0 * s2 + s) * h
        h01 = 3.0 * s2 - 2.0 * s3
        h11 = (s3 - s2) * h
        for c in range(sensor_q.shape[1]):
            sensor_q[i0 + k, c] = (h00 * sensor_q[i0, c] + h10 * sensor_v[i0, c]
                                   + h01 * sensor_q[i1, c] + h11 * sensor_v[i1, c])
            sensor_v[i0 + k, c] = (h00 * sensor_v[i0, c] + h10 * sensor_a[i0, c]
                                   + h01 * sensor_v[i1, c] + h11 * sensor_a[i1, c])
            sensor_a[i0 + k, c] = (1.0 - s) * sensor_a[i0, c] + s * sensor_a[i1, c]
