"""Result of one dynamic simulation: time histories, metrics, energy balance, saving."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from .._display import Headline, draw, figure, number, without_status
from .._files import atomic_write
from ..errors import InputFileError
from ..units import ARCMIN
from ..physics import _layout as L

__all__ = ["Result", "te_metrics", "te_spectrum", "crank_frequency", "ate_note",
           "channel_unit", "CHANNEL_UNITS"]


def crank_frequency(time: np.ndarray, omega_out: np.ndarray, steady_start: float,
                    pin_count: int) -> float:
    """Mean rate of the crank rotation relative to the carrier over the steady window [Hz]:
    the unit of the spectrum's orders (the crank turns ``pin_count`` times faster than the
    carrier, relative to it)."""
    window = time >= steady_start - 1e-12
    if not window.any():
        return 0.0
    return float(abs(np.mean(omega_out[window])) * pin_count / (2.0 * np.pi))


def te_spectrum(time: np.ndarray, te: np.ndarray, omega_out: np.ndarray, steady_start: float,
                pin_count: int):
    """Amplitude spectrum of the steady TE [arcmin] against orders of the crank rotation
    relative to the carrier (which turns ``pin_count`` times faster than the carrier).

    Hann window, mean removed, amplitudes corrected for the window.  Returns
    (orders, amplitude_arcmin).
    """
    window = time >= steady_start - 1e-12
    signal = te[window] / ARCMIN
    signal = signal - signal.mean()
    n = len(signal)
    if n < 8:
        return np.zeros(0), np.zeros(0)
    dt = time[1] - time[0]
    amplitude = 2.0 * np.abs(np.fft.rfft(signal * np.hanning(n))) / (0.5 * n)
    freq = np.fft.rfftfreq(n, dt)
    crank_hz = crank_frequency(time, omega_out, steady_start, pin_count)
    return (freq / crank_hz if crank_hz > 0 else freq), amplitude


def te_metrics(time: np.ndarray, te: np.ndarray, omega_in: np.ndarray, omega_out: np.ndarray,
               steady_start: float) -> dict[str, float]:
    """Summary metrics over the steady window t >= steady_start (TE in arcmin)."""
    window = time >= steady_start - 1e-12
    if not window.any():
        nan = float("nan")
        return dict.fromkeys(("te_mean_arcmin", "te_pp_arcmin", "te_rms_arcmin", "te_std_arcmin",
                              "te_max_arcmin", "speed_ratio"), nan)
    te_w = te[window] / ARCMIN
    return {
        "te_mean_arcmin": float(np.mean(te_w)),
        "te_pp_arcmin": float(np.ptp(te_w)),
        "te_rms_arcmin": float(np.sqrt(np.mean(te_w ** 2))),
        "te_std_arcmin": float(np.std(te_w)),
        "te_max_arcmin": float(np.max(te_w)),
        "speed_ratio": float(np.mean(omega_in[window]) / np.mean(omega_out[window])),
    }


#: the unit suffix of each kind of channel (by its name's first word); forces the rest [N]
CHANNEL_UNITS = {"time": "s", "theta": "rad", "omega": "rad_per_s", "torque": "nm"}


def channel_unit(name: str) -> str:
    """The unit suffix of the channel ``name`` in a frame's column name."""
    return CHANNEL_UNITS.get(name.split("_")[0], "n")


def ate_note(revolutions: float) -> str:
    """Why a run has no ATE: its steady window covers ``revolutions`` (< 1) of an output
    revolution."""
    return (f"no ATE: the steady window covers {revolutions:.3g} of an output revolution "
            "(the ATE needs one); te_pp_arcmin is the peak-to-peak over that part of one")


@dataclasses.dataclass(repr=False)
class Result(Headline):
    """Histories (SI) sampled at ``time`` and the summary of one run.

    ``te`` is theta_in / i - theta_out (Eq. 22) [rad]; metrics are in arcmin.  Shown as its
    headline figures (:meth:`headline`); ``plot()`` draws the TE over time.
    """

    time: np.ndarray
    channels: np.ndarray
    pin_forces: np.ndarray
    """contact force of each pin on each disc [N], shape (samples, 2, zp)"""
    ratio: float
    steady_start: float
    status: str
    steps: int
    wall_s: float
    energy: dict[str, float]
    reducer_name: str = "RV-40E"
    guard: dict[str, float] = dataclasses.field(default_factory=dict)
    """what the crank nodes' stability guard did (steps above 6e-6 s only; docs/model.md
    section 9): ``guard_substep_checks`` (whole run) and ``guard_substep_checks_steady``
    (steady window) count its checks after which the step was divided into sub-steps,
    ``guard_peak_omega_dt`` is the largest omega dt (of the whole step) of the node modes it
    found; empty when the guard was off.  With the scheme implicit-bearings (which needs no
    guard) instead: ``implicit_factorisations`` of M + theta h^2 K_b, ``implicit_alerts`` (of
    them brought forward by a bearing's rising force) and ``implicit_fallbacks`` (steps taken
    explicitly: that matrix not positive definite)"""

    pin_force_peak: float = float("nan")
    """the largest pin force of the steady window over every (sub-)step of the solver [N];
    NaN where unknown (a Result built from histories alone: the samples' maximum is used)"""

    def channel(self, name: str) -> np.ndarray:
        return self.channels[:, L.CHANNEL_NAMES.index(name)]

    @property
    def theta_in(self) -> np.ndarray:
        return self.channel("theta_in")

    @property
    def theta_out(self) -> np.ndarray:
        return self.channel("theta_out")

    @property
    def omega_in(self) -> np.ndarray:
        return self.channel("omega_in")

    @property
    def omega_out(self) -> np.ndarray:
        return self.channel("omega_out")

    @property
    def te(self) -> np.ndarray:
        return self.theta_in / self.ratio - self.theta_out

    @property
    def mesh_forces(self) -> np.ndarray:
        return self.channels[:, L.CH_MESH_F0:L.CH_MESH_F0 + 2]

    @property
    def arm_bushing_forces(self) -> np.ndarray:
        """shape (samples, crank, disc) [N]"""
        return self.channels[:, L.CH_ARM_F00:L.CH_ARM_F00 + 4].reshape(-1, 2, 2)

    @property
    def support_forces(self) -> np.ndarray:
        """shape (samples, crank, (lower, upper)) [N]"""
        return self.channels[:, L.CH_SUP_FL0:L.CH_SUP_FL0 + 4].reshape(-1, 2, 2)

    @property
    def metrics(self) -> dict[str, float]:
        m = te_metrics(self.time, self.te, self.omega_in, self.omega_out, self.steady_start)
        window = self.time >= self.steady_start - 1e-12
        m["energy_residual"] = self.energy.get("relative_residual", float("nan"))
        if not window.any():                # stopped before the window: no answer
            m["max_pin_force_n"] = float("nan")
        elif np.isfinite(self.pin_force_peak):      # every step's, not the samples'
            m["max_pin_force_n"] = self.pin_force_peak
        else:
            m["max_pin_force_n"] = float(self.pin_forces[window].max())
        m.update(self.ate())
        return m

    def ate(self) -> dict[str, float]:
        """``ate_arcmin``: the angular transmission error (peak-to-peak TE over one output
        revolution, :func:`rvsim.analysis.catalogue.angular_transmission_error`) of the steady
        window, NaN when the window covers less than a revolution (then ``te_pp_arcmin`` is
        the peak-to-peak over a part of one); ``te_window_revolutions``: the output
        revolutions the steady window covers (docs/decisions.md, issue 33)."""
        from ..analysis.catalogue import angular_transmission_error

        window = self.time >= self.steady_start - 1e-12
        angle, te = self.theta_out[window], self.te[window]
        if not (np.isfinite(angle).all() and np.isfinite(te).all()):    # a run that blew up
            return {"ate_arcmin": float("nan"), "te_window_revolutions": float("nan")}
        ate, covered = angular_transmission_error(angle, te / ARCMIN)   # as te_pp_arcmin
        return {"ate_arcmin": ate, "te_window_revolutions": covered}

    def summary(self) -> dict:
        """The JSON object ``rvsim simulate --json`` prints (with ``ate_note`` saying why
        ``ate_arcmin`` is null when the steady window covers less than an output revolution)."""
        out = {**self.metrics, "sim_time_s": float(self.time[-1]) if len(self.time) else 0.0,
               "steps": self.steps, "wall_s": self.wall_s, "status": self.status,
               "reducer": self.reducer_name, **self.guard}
        if not np.isfinite(out["ate_arcmin"]) and np.isfinite(out["te_window_revolutions"]):
            out["ate_note"] = ate_note(out["te_window_revolutions"])
        return out

    def headline(self) -> tuple[str, list[tuple]]:
        """Status, time simulated and the report's opening rows
        (:func:`rvsim.analysis.headline.run_rows`): the repr."""
        from ..analysis.headline import run_rows

        m = self.summary()
        rows = without_status(run_rows(m))
        rows.append(("energy residual", number(m["energy_residual"], "of the input work", 2)))
        if "ate_note" in m:
            rows.append(("note", m["ate_note"]))
        return (f"Result of {self.reducer_name}: {m['status']}, {number(m['sim_time_s'], 's')} "
                f"simulated ({m['steps']} steps, {number(m['wall_s'], 's', 3)} wall)", rows)

    def plot(self, ax=None):
        """TE [arcmin] over the steady window, the whole run with its start-up in an inset
        (:func:`rvsim.plots.te_plot`); returns the Axes."""
        return draw(figure("rvsim.plots", "te_plot"), ax, {self.reducer_name: self},
                    self.steady_start)

    def spectrum(self, pin_count: int | None = None):
        """Steady-window TE spectrum: DataFrame of ``order`` (crank rotation relative to the
        carrier) and ``amplitude_arcmin``; ``pin_count`` defaults to the run's own (it was a
        fixed 40, the RV-40E's, whatever the reducer)."""
        import pandas as pd

        if pin_count is None:
            pin_count = self.pin_forces.shape[-1]
        orders, amplitude = te_spectrum(self.time, self.te, self.omega_out, self.steady_start,
                                        pin_count)
        return pd.DataFrame({"order": orders, "amplitude_arcmin": amplitude})

    def to_frame(self):
        """Time histories as a pandas DataFrame, SI with the unit in each column name
        (``time_s``, ``theta_in_rad``, ``omega_out_rad_per_s``, ``torque_in_nm``,
        ``mesh_f0_n`` ...; TE in rad and arcmin).  The .npz of :meth:`save` keeps the
        channels' plain names."""
        import pandas as pd

        data = {f"{name}_{channel_unit(name)}": self.channels[:, i]
                for i, name in enumerate(L.CHANNEL_NAMES)}
        data["te_rad"] = self.te
        data["te_arcmin"] = self.te / ARCMIN
        return pd.DataFrame(data)

    def save(self, path: str | Path) -> Path:
        """Write histories and summary to a NumPy ``.npz`` file (atomically)."""
        path = Path(path)
        if path.suffix.lower() != ".npz":
            raise InputFileError(f"{path}: histories are saved as .npz (numpy.load reads them)")
        if not path.parent.exists():
            raise InputFileError(f"{path}: folder {path.parent} does not exist")
        arrays = {name: self.channels[:, i] for i, name in enumerate(L.CHANNEL_NAMES)}

        def write(tmp: Path) -> None:
            with open(tmp, "wb") as handle:
                np.savez_compressed(handle, **arrays, te_rad=self.te,
                                    pin_forces=self.pin_forces,
                                    summary=json.dumps(self.summary()))
        return atomic_write(path, write)
