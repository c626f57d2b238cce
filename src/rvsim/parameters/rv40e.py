"""The RV-40E reducer of the source paper, and its L36 study factors.

Source: "Influencing Factors on Rotate Vector Reducer Dynamic Transmission Error",
Int. J. of Automation Technology (paper text in shared/paper), Tables 2, 4 and 5, Sec. 3.3.
Part sizes the paper does not give (bushing radii, axial stations, carrier size) are assumptions
documented in docs/model.md.
"""

from __future__ import annotations

import dataclasses
import math

from ._types import Operating, Reducer

__all__ = ["RV40E", "CITATION", "TABLE2_FACTORS", "FactorSpec"]

CITATION = ("Influencing Factors on Rotate Vector Reducer Dynamic Transmission Error "
            "(RV-40E; Tables 2, 4, 5 and Sec. 3.3)")

#: the paper's RV-40E: every error zero, constant 300 N*m load (middle level of factor E)
RV40E = Reducer(name="RV-40E", citation=CITATION, operating=Operating())


@dataclasses.dataclass(frozen=True)
class FactorSpec:
    """One factor of the paper's Table 2: the parameter it sets and its levels (user units)."""

    letter: str
    parameter: str
    description: str
    levels: tuple


#: Table 2; levels in the user units of each parameter (mm, N*m, flags)
TABLE2_FACTORS: dict[str, FactorSpec] = {f.letter: f for f in (
    FactorSpec("A", "flexibility.cycloid_disc", "cycloid gear is a flexible body", (True, False)),
    FactorSpec("B", "flexibility.pin", "pin gear is a flexible body", (True, False)),
    FactorSpec("C", "flexibility.arm_bushing", "arm bushing is a flexible body", (True, False)),
    FactorSpec("D", "operating.load_fluctuation", "load fluctuates", (True, False)),
    FactorSpec("E", "operating.load_torque", "load size [N*m]", (200.0, 300.0, 400.0)),
    FactorSpec("F", "errors.pin_radius", "pin gear radius error [mm]", (0.01, 0.02, 0.03)),
    FactorSpec("G", "errors.eccentricity", "crankshaft eccentricity error [mm]",
               (0.005, 0.01, 0.015)),
    FactorSpec("H", "errors.pin_circle_radius", "pin gear centre circle radius error [mm]",
               (0.01, 0.02, 0.03)),
    FactorSpec("I", "errors.equidistant_modification",
               "cycloid equidistant modification [mm]", (0.016, 0.032, 0.048)),
    FactorSpec("J", "errors.radial_modification", "cycloid radial-moving modification [mm]",
               (0.026, 0.052, 0.078)),
    FactorSpec("K", "clearances.crank_arm_bushing", "crankshaft - arm bushing clearance [mm]",
               (0.0, 0.005, 0.01)),
    FactorSpec("L", "clearances.support_flange", "support bushing - flange clearance [mm]",
               (0.0, 0.005, 0.01)),
    FactorSpec("M", "clearances.disc_arm_bushing",
               "cycloid inner hole - arm bushing clearance [mm]", (0.0, 0.005, 0.01)),
    FactorSpec("N", "clearances.support_carrier", "support bushing - carrier clearance [mm]",
               (0.0, 0.005, 0.01)),
    FactorSpec("O", "clearances.crank_support_bushing",
               "crankshaft - support bushing clearance [mm]", (0.0, 0.005, 0.01)),
)}

assert math.isclose(RV40E.ratio, 121.0)


def paper_l36_scheme():
    """The paper's L36 scheme (Table 3, repaired rows; levels index Table 2) with its TE.

    Returns a pandas DataFrame with columns run, A..O (level numbers), te_arcmin, note.
    """
    from importlib.resources import files

    import pandas as pd

    with files("rvsim.data").joinpath("paper_l36.csv").open("r", encoding="utf-8") as handle:
        return pd.read_csv(handle, comment="#", keep_default_na=False,
                           dtype={"note": str})


def paper_run_values(run: int) -> dict[str, object]:
    """Factor values (user units, by letter) of row ``run`` (1..36) of the paper's L36."""
    from ..errors import ParameterError

    scheme = paper_l36_scheme()
    if not (isinstance(run, int) and 1 <= run <= len(scheme)):
        raise ParameterError("paper-run", f"must be a run number from 1 to {len(scheme)} "
                             f"(got {run})")
    row = scheme[scheme["run"] == run].iloc[0]
    return {letter: spec.levels[int(row[letter]) - 1] for letter, spec in TABLE2_FACTORS.items()}
