"""Make docs/examples/hysteresis_loop.csv: a torque-reversal curve as a bench exports it,
synthetic (rvsim's own quasi-static model with known parameters), for the calibration
walk-through of docs/user_guide.md section 9.

    python scripts/make_loop_example.py

The "true" reducer is the built-in RV-40E with the stiffness scalings and the clearance of
TRUE; the curve is its torque-reversal test to the rated 412 N*m at 20 steps per quarter (the
standard sweep, 101 samples), the twist with 0.1 arcsec of Gaussian encoder noise (seed 7),
quantised to an output encoder of 2^23 counts per revolution (0.154 arcsec) and shifted by an
arbitrary zero of 1.5 arcmin.
"""

from pathlib import Path

import numpy as np

from rvsim.parameters import RV40E, with_values
from rvsim.quasistatic import hysteresis
from rvsim.testrig.curves import loop_table

#: the reducer on the bench (user units: the clearance in mm): what the fit should find
TRUE = {"stiffness.pins": 0.8, "stiffness.arm_bearings": 0.7,
        "clearances.crank_arm_bushing": 0.004}
NOISE_ARCSEC = 0.1
COUNTS = 2 ** 23
ZERO_ARCMIN = 1.5
SEED = 7

OUT = Path(__file__).resolve().parents[1] / "docs" / "examples" / "hysteresis_loop.csv"


def make():
    """The example loop (pandas DataFrame, the columns of ``rvsim hysteresis --csv``)."""
    table = loop_table(hysteresis(with_values(RV40E, TRUE), points_per_branch=20))
    rng = np.random.default_rng(SEED)
    step = 360.0 * 60.0 / COUNTS                       # arcmin per count
    twist = table["twist_arcmin"] + ZERO_ARCMIN + rng.normal(0.0, NOISE_ARCSEC / 60.0,
                                                             len(table))
    table["twist_arcmin"] = np.floor(twist / step) * step
    return table


if __name__ == "__main__":
    table = make()
    table.to_csv(OUT, index=False, float_format="%.10g")
    print(f"wrote {OUT} ({len(table)} rows)")
