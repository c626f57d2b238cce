"""Modes of a finite-element disc in the dynamic kernel (numba; docs/model.md section 17,
"Modes and Craig-Bampton reduction").

With ``flexibility.fe_modes`` = n > 0 each disc carries n modal coordinates eta of its lowest
modes held at the crank holes (mass-normalised, free interface; :func:`rvsim.fe.modes.
free_interface`), integrated with the kernel's semi-implicit Euler step:

    eta'' + 2 zeta Omega eta' + Omega^2 eta = P^T f,

f the elastic forces of the touching pins spread on the contact segments with the weights the
compliance table is read with (linear between segment centres), P the modes' mean normal
displacement over the segments.  A pin's contact sees the disc's deflection (P eta)(u) at its
foot u plus the residual R's (massless, the modes left out), which replaces the condensed
table C in the Gauss-Seidel sweep (:func:`rvsim.physics._fe_contacts.lagged_forces`).  Static:
eta = Omega^-2 P^T f, so the deflection is (P Omega^-2 P^T + R) f = C f, whatever n (read
between segment centres as the table is: :func:`foot_modes`).

A disc's array ``modal`` (m + HEADER, n) holds P in rows 0..m-1 and, from row m, Omega^2,
Omega^-2, Omega (constants: no division or root in the step), eta, eta' and the modal force
P^T f that the contacts of the current evaluation accumulate (:func:`modal_array` builds it).
With n = 0 every loop is empty and the contacts are those of the condensed disc.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._jit import NO_REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

__all__ = ["OMEGA2", "INV_OMEGA2", "OMEGA", "ETA", "RATE", "FORCE", "HEADER", "modal_array",
           "foot_modes", "add_modal_force", "clear_modal_force", "advance_modes",
           "modal_energy"]

#: rows of a disc's modal array after its m participation rows: modal[m + OMEGA2] ...
OMEGA2, INV_OMEGA2, OMEGA, ETA, RATE, FORCE = range(6)
HEADER = 6


def modal_array(participation: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """The kernel's modal array (discs, m + HEADER, n) of discs with participation P (discs,
    m, n) and circular frequencies ``omega`` (n,) [rad/s], at rest."""
    discs, m, n = participation.shape
    modal = np.zeros((discs, m + HEADER, n))
    modal[:, :m] = participation
    modal[:, m + OMEGA2] = omega ** 2
    modal[:, m + INV_OMEGA2] = 1.0 / omega ** 2
    modal[:, m + OMEGA] = omega
    return modal


@numba.njit(**NO_REFCOUNT)
def foot_modes(modal, i0, i1, frac):
    """At a foot parameter u between segment centres i0 and i1 (weight ``frac`` of i1): the
    modes' normal deflection (P eta)(u) [m], and the own compliance that the pin adds to the
    residual's so that its statics is the condensed table's [m/N].  The table reads a pin's
    own compliance linearly along the diagonal, (1 - s) C_00 + s C_11, the modes bilinearly,
    w^T M w with M = P Omega^-2 P^T and w = (1 - s, s); the difference is
    s (1 - s) (M_00 + M_11 - 2 M_01) = s (1 - s) sum_k (P_0k - P_1k)^2 / Omega_k^2."""
    m = modal.shape[0] - HEADER
    deflection = 0.0
    total = 0.0
    for k in range(modal.shape[1]):
        p0, p1 = modal[i0, k], modal[i1, k]
        deflection += ((1.0 - frac) * p0 + frac * p1) * modal[m + ETA, k]
        diff = p0 - p1
        total += diff * diff * modal[m + INV_OMEGA2, k]
    return deflection, frac * (1.0 - frac) * total


@numba.njit(**NO_REFCOUNT)
def add_modal_force(modal, i0, i1, frac, force):
    """Add the modal force (P^T f) of an inward normal ``force`` at a foot between segment
    centres i0 and i1 (weight ``frac`` of i1)."""
    n = modal.shape[1]
    if n == 0:
        return
    m = modal.shape[0] - HEADER
    for k in range(n):
        modal[m + FORCE, k] += ((1.0 - frac) * modal[i0, k] + frac * modal[i1, k]) * force


@numba.njit(**NO_REFCOUNT)
def clear_modal_force(modal):
    """Zero the modal force before the contacts of an evaluation add theirs."""
    m = modal.shape[0] - HEADER
    for k in range(modal.shape[1]):
        modal[m + FORCE, k] = 0.0


@numba.njit(**NO_REFCOUNT)
def advance_modes(modal, dt, zeta):
    """One semi-implicit Euler step of the modal coordinates under the modal force of the
    step's evaluation (velocities first, then positions); returns the power the modal damping
    2 zeta Omega dissipates at the velocities of the start of the step."""
    m = modal.shape[0] - HEADER
    power = 0.0
    for k in range(modal.shape[1]):
        damping = 2.0 * zeta * modal[m + OMEGA, k]
        rate = modal[m + RATE, k]
        power += damping * rate * rate
        modal[m + RATE, k] = rate + dt * (modal[m + FORCE, k] - modal[m + OMEGA2, k]
                                          * modal[m + ETA, k] - damping * rate)
        modal[m + ETA, k] += dt * modal[m + RATE, k]
    return power


@numba.njit(**NO_REFCOUNT)
def modal_energy(modal):
    """(kinetic, strain) energy of the disc's modes [J] (mass-normalised coordinates)."""
    m = modal.shape[0] - HEADER
    kinetic = 0.0
    strain = 0.0
    for k in range(modal.shape[1]):
        kinetic += 0.5 * modal[m + RATE, k] ** 2
        strain += 0.5 * modal[m + OMEGA2, k] * modal[m + ETA, k] ** 2
    return kinetic, strain
