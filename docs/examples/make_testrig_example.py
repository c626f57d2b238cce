"""Make the example bench recordings of docs/examples/testrig/ (synthetic: rvsim's own model
with known parameters, encoder quantisation, noise, an arbitrary input-encoder zero).

    python docs/examples/make_testrig_example.py
"""

from pathlib import Path

from rvsim.parameters import RV40E, with_values
from rvsim.testrig import synthetic

#: the "true" reducer on the bench (what calibration should find)
TRUE = {"errors.equidistant_modification": 0.01, "errors.disc_runout": 0.006,
        "clearances.crank_arm_bushing": 0.004, "contact.bushing_stiffness_factor": 0.8}

if __name__ == "__main__":
    folder = Path(__file__).parent / "testrig"
    folder.mkdir(exist_ok=True)
    reducer = with_values(RV40E, TRUE)
    te, _ = synthetic.te_recording(reducer, torque=300.0, backward=True, revolutions=1.05,
                                   samples_per_revolution=4000, zero_out=0.0,
                                   model_points=1024, seed=12)
    te.to_csv(folder / "te_15rpm_300Nm_40C.csv", index=False, float_format="%.10g")
    loop, _ = synthetic.reversal_recording(reducer, samples=4000, seed=13)
    loop.to_csv(folder / "reversal.csv", index=False, float_format="%.10g")
