"""Modal analysis and Craig-Bampton reduction of a finite-element body (docs/model.md section
17, "Modes and Craig-Bampton reduction").

The body's *interface* is its set of boundary loads b_i (the columns of ``loads``, the contact
segments of :mod:`rvsim.fe.disc`); its interface coordinate q_i = b_i^T u is the traction-
weighted mean displacement over load i, the same functional the static condensation uses.
With the supports held (the crank-hole edges of the disc):

* **constraint modes** Psi = K^-1 B C^-1 (C = B^T K^-1 B the condensed compliance): the least-
  energy displacement with q = e_j, so B^T Psi = I and Psi^T K Psi = C^-1;
* **fixed-interface modes** Phi: K phi = omega^2 M phi with B^T phi = 0 (q held at zero), the
  lowest ``modes`` of them, mass-normalised; they are K-orthogonal to Psi (Phi^T K Psi =
  (B^T Phi)^T C^-1 = 0).

The reduced model on (q, eta) is K_r = T^T K T = diag(C^-1, Omega^2), M_r = T^T M T with
T = [Psi Phi]
(Craig & Bampton, AIAA J. 6 (1968) 1313, with the interface's nodal dofs replaced by the
segment functionals).  Its static interface compliance is C exactly, whatever the number of
modes; its eigenfrequencies are Rayleigh-Ritz upper bounds of the supported body's and
converge to them as modes are added.  The eigenproblems are solved in shift-invert mode about
zero (ARPACK through scipy.sparse.linalg.eigsh) with the sparse Cholesky factor of K; the
interface constraint enters as the constrained inverse G = K^-1 - X C^-1 X^T, X = K^-1 B, whose
range is the constrained subspace.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, eigsh

from ..parameters import Reducer
from . import cache
from .elasticity import PlaneStressBody, _dense

__all__ = ["CraigBampton", "FreeInterface", "MAX_OMEGA_DT", "craig_bampton",
           "disc_craig_bampton", "disc_free_interface", "disc_frequencies", "disc_modal_arrays",
           "free_interface", "spring_frequencies", "supported_modes"]


@dataclasses.dataclass(frozen=True)
class CraigBampton:
    """A Craig-Bampton reduced body: ``stiffness`` and ``mass`` on (q, eta), the first
    ``interfaces`` coordinates the interface ones."""

    stiffness: np.ndarray           # (n_i + modes) square [N/m, modal coordinates in kg^0.5 m]
    mass: np.ndarray                # same shape [kg]
    interfaces: int
    modes: int
    fixed_interface_hz: np.ndarray  # (modes,) frequencies of the fixed-interface modes [Hz]
    compliance: np.ndarray          # (n_i, n_i) condensed compliance C [m/N]

    def frequencies(self) -> np.ndarray:
        """Eigenfrequencies of the reduced model, ascending [Hz]."""
        w2 = scipy.linalg.eigh(self.stiffness, self.mass, eigvals_only=True)
        return np.sqrt(np.maximum(w2, 0.0)) / (2.0 * math.pi)

    def static_compliance(self) -> np.ndarray:
        """Interface compliance of the reduced model: (K_r^-1) restricted to q [m/N]."""
        return np.linalg.inv(self.stiffness)[:self.interfaces, :self.interfaces]


def _shift_invert(k_free: sp.spmatrix, m_free: sp.spmatrix, apply_inverse, count: int
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``count`` eigenpairs of K x = w^2 M x with the inverse (or constrained inverse)
    of K given as ``apply_inverse``; mass-normalised shapes."""
    n = k_free.shape[0]
    op = LinearOperator((n, n), matvec=apply_inverse, dtype=float)
    w2, shapes = eigsh(k_free, k=count, M=m_free, sigma=0.0, which="LM", OPinv=op,
                       tol=1e-12)
    order = np.argsort(w2)
    w2, shapes = w2[order], shapes[:, order]
    shapes /= np.sqrt(np.einsum("ij,ij->j", shapes, m_free @ shapes))
    return w2, shapes


def supported_modes(body: PlaneStressBody, density: float, supported: np.ndarray,
                    count: int) -> tuple[np.ndarray, np.ndarray]:
    """The lowest ``count`` natural frequencies [Hz] and mass-normalised mode shapes (free
    dofs x count) of ``body`` with the ``supported`` dofs held."""
    factor = body.factor(supported)
    free = factor.free
    k = body.stiffness[free][:, free]
    m = body.mass(density)[free][:, free]
    w2, shapes = _shift_invert(k, m, factor.solve, count)
    return np.sqrt(w2) / (2.0 * math.pi), shapes


def craig_bampton(body: PlaneStressBody, density: float, loads, supported: np.ndarray,
                  modes: int) -> CraigBampton:
    """Craig-Bampton reduction of ``body`` onto the interface functionals ``loads`` (n_dofs x
    n_i) plus ``modes`` fixed-interface modes (``modes`` >= 0)."""
    factor = body.factor(supported)
    free = factor.free
    b = _dense(loads[free])
    x = factor.solve(b)                                 # K^-1 B
    c = b.T @ x
    c = 0.5 * (c + c.T)
    c_inv = np.linalg.inv(c)
    c_inv = 0.5 * (c_inv + c_inv.T)
    psi = x @ c_inv                                     # constraint modes, B^T Psi = I
    m = body.mass(density)[free][:, free]
    n_i = b.shape[1]
    k = body.stiffness[free][:, free]
    if modes > 0:
        def constrained_inverse(v):
            return factor.solve(v) - x @ (c_inv @ (x.T @ v))

        w2, phi = _shift_invert(k, m, constrained_inverse, modes)
    else:
        w2, phi = np.zeros(0), np.zeros((len(free), 0))
    basis = np.hstack([psi, phi])
    mass = basis.T @ (m @ basis)
    # T^T K T from the basis itself (not the closed form diag(C^-1, Omega^2)), so that the
    # verification of the reduced statics checks the modes
    stiffness = basis.T @ (body.stiffness[free][:, free] @ basis)
    return CraigBampton(0.5 * (stiffness + stiffness.T), 0.5 * (mass + mass.T), n_i, modes,
                        np.sqrt(w2) / (2.0 * math.pi), c)


@dataclasses.dataclass(frozen=True)
class FreeInterface:
    """Free-interface modes with residual flexibility (MacNeal 1971, Craig & Chang 1977): the
    form an explicit integrator can take.  With modal coordinates eta (mass-normalised modes
    of the supported body, interface loads free) and interface forces f on the segments:

        eta'' + Omega^2 eta = P^T f,    q = P eta + R f,

    P = B^T Phi (n_i x modes) the modes' mean displacements over the segments, R = C - P
    Omega^-2 P^T the residual (massless) compliance of the modes left out.  Static: q = C f
    exactly, whatever the number of modes."""

    frequencies_hz: np.ndarray      # (modes,)
    participation: np.ndarray       # P (n_i, modes) [m per modal unit]
    residual: np.ndarray            # R (n_i, n_i) [m/N]
    compliance: np.ndarray          # C (n_i, n_i) [m/N]

    def with_springs(self, stiffness: np.ndarray) -> np.ndarray:
        """Natural frequencies [Hz] of the reduced body with a spring of ``stiffness`` [N/m]
        (n_i,) from each segment to the ground (contacts held at their tangent stiffness):
        the modal equations with f = -k q eliminated."""
        k = np.diag(stiffness)
        n_i = len(stiffness)
        back = np.linalg.solve(np.eye(n_i) + k @ self.residual, k @ self.participation)
        omega2 = np.diag((2.0 * math.pi * self.frequencies_hz) ** 2)
        w2 = scipy.linalg.eigvalsh(omega2 + self.participation.T @ back)
        return np.sqrt(np.maximum(w2, 0.0)) / (2.0 * math.pi)


def free_interface(body: PlaneStressBody, density: float, loads, supported: np.ndarray,
                   modes: int) -> FreeInterface:
    """Free-interface reduction of ``body`` on the interface loads ``loads`` with the lowest
    ``modes`` modes of the supported body."""
    factor = body.factor(supported)
    free = factor.free
    b = _dense(loads[free])
    c = b.T @ factor.solve(b)
    c = 0.5 * (c + c.T)
    if modes > 0:
        k = body.stiffness[free][:, free]
        m = body.mass(density)[free][:, free]
        w2, phi = _shift_invert(k, m, factor.solve, modes)
    else:
        w2, phi = np.zeros(0), np.zeros((len(free), 0))
    p = b.T @ phi
    residual = c - (p / w2) @ p.T if modes > 0 else c.copy()
    return FreeInterface(np.sqrt(w2) / (2.0 * math.pi), p, 0.5 * (residual + residual.T), c)


def spring_frequencies(body: PlaneStressBody, density: float, loads, supported: np.ndarray,
                       stiffness: np.ndarray, count: int) -> np.ndarray:
    """The lowest ``count`` natural frequencies [Hz] of the full body with a spring of
    ``stiffness`` [N/m] on each interface functional (K + B k B^T): the reference of
    :meth:`FreeInterface.with_springs`."""
    free = np.setdiff1d(np.arange(body.n_dofs), supported)
    b = sp.csc_matrix(loads)[free]
    k = (body.stiffness[free][:, free] + b @ sp.diags(stiffness) @ b.T).tocsc()
    m = body.mass(density)[free][:, free]
    w2 = eigsh(k, k=count, M=m, sigma=0.0, which="LM", return_eigenvectors=False)
    return np.sqrt(np.sort(w2)) / (2.0 * math.pi)


def _disc(reducer: Reducer):
    from .disc import disc_body, disc_geometry

    g = disc_geometry(reducer, 0)
    body, supported, loads = disc_body(g)
    return g, body, supported, loads


def disc_frequencies(reducer: Reducer, count: int) -> np.ndarray:
    """The lowest ``count`` natural frequencies of disc 1 held at its crank holes [Hz] (the
    mesh of ``flexibility.fe_element_size``)."""
    _, body, supported, _ = _disc(reducer)
    return supported_modes(body, reducer.materials.cycloid_disc.density, supported, count)[0]


def _disc_reduction(reducer: Reducer, kind: str, modes: int, reduce
                    ) -> tuple[dict, float, bool]:
    """``reduce(body, density, loads, supported, modes)`` (a dict of arrays) of disc 1, cached
    by the disc's geometry hash, its density and ``modes``: (arrays, seconds, from cache)."""
    from .disc import disc_geometry

    g = disc_geometry(reducer, 0)
    density = reducer.materials.cycloid_disc.density

    def compute():
        _, body, supported, loads = _disc(reducer)
        return reduce(body, density, loads, supported, modes)

    return cache.cached(kind, {**g, "density": density, "modes": modes}, compute)


def disc_craig_bampton(reducer: Reducer, modes: int) -> tuple[CraigBampton, float, bool]:
    """The Craig-Bampton model of disc 1 on its contact segments with ``modes`` fixed-interface
    modes: (model, seconds to build, loaded from the cache).  Cached by the disc's geometry
    hash, its density and ``modes``."""
    def reduce(*args):
        model = craig_bampton(*args)
        return {"stiffness": model.stiffness, "mass": model.mass,
                "interfaces": np.array(model.interfaces),
                "fixed_interface_hz": model.fixed_interface_hz, "compliance": model.compliance}

    a, seconds, from_cache = _disc_reduction(reducer, "cycloid-disc-craig-bampton", modes,
                                             reduce)
    return (CraigBampton(a["stiffness"], a["mass"], int(a["interfaces"]), modes,
                         a["fixed_interface_hz"], a["compliance"]), seconds, from_cache)


def disc_free_interface(reducer: Reducer, modes: int) -> tuple[FreeInterface, float, bool]:
    """The free-interface model of disc 1 (:func:`free_interface`, the form the dynamic kernel
    integrates) with its lowest ``modes`` modes: (model, seconds to build, loaded from the
    cache).  Cached by the disc's geometry hash, its density and ``modes``."""
    a, seconds, from_cache = _disc_reduction(
        reducer, "cycloid-disc-free-interface", modes,
        lambda *args: dataclasses.asdict(free_interface(*args)))
    return (FreeInterface(a["frequencies_hz"], a["participation"],
                          a["residual"], a["compliance"]), seconds, from_cache)


#: largest omega * dt of a disc mode that the dynamic kernel integrates (docs/decisions.md,
#: "Disc modes in the dynamic kernel"): the semi-implicit Euler step is stable up to 2 and
#: turns a mode of omega into one of (2 / dt) asin(omega dt / 2), 4.7 % fast at 1; the pin
#: contacts raise the top frequency of the coupled system by 1.2-1.8x (measured at 1-3e9 N/m
#: per pin), which 1 keeps below 2
MAX_OMEGA_DT = 1.0


def disc_modal_arrays(reducer: Reducer, tables: np.ndarray, modes: int, time_step: float
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both discs with ``modes`` modes each, as the dynamic kernel integrates them, from their
    condensed ``tables`` (2, m, m): (residual tables R (2, m, m) that replace the condensed ones
    in the contacts, participation P (2, m, modes), circular frequencies Omega (modes,)
    [rad/s]).  With 0 modes, R is ``tables`` itself.

    A mode above omega dt = :data:`MAX_OMEGA_DT` raises ParameterError on
    ``flexibility.fe_modes``.  Disc 2 is disc 1 turned half a turn: for an odd tooth count
    its R and P are disc 1's shifted by (zc + 1) / 2 teeth of segments (as
    :func:`rvsim.fe.disc.disc_tables`); an even count would need its own modes (refused)."""
    from ..errors import ParameterError

    m = tables.shape[1]
    if modes == 0:
        return tables, np.zeros((2, m, 0)), np.zeros(0)
    zc = reducer.cycloid.disc_teeth
    if zc % 2 == 0:
        raise ParameterError("flexibility.fe_modes", "the disc modes need an odd tooth count "
                             "(disc 2 is then disc 1 turned by whole teeth); use 0")
    model = disc_free_interface(reducer, modes)[0]
    omega = 2.0 * math.pi * model.frequencies_hz
    admissible = int(np.sum(omega * time_step <= MAX_OMEGA_DT))
    if admissible < modes:
        raise ParameterError(
            "flexibility.fe_modes", f"{modes} modes reach {model.frequencies_hz[-1] / 1e3:.3g}"
            f" kHz, beyond what the time step {time_step:g} s integrates (omega dt <= "
            f"{MAX_OMEGA_DT:g}): at most {admissible} at this step")
    shift = (zc + 1) // 2 * reducer.flexibility.fe_segments_per_tooth
    residual = np.stack([model.residual, np.roll(model.residual, shift, axis=(0, 1))])
    participation = np.stack([model.participation, np.roll(model.participation, shift, axis=0)])
    return residual, participation, omega
