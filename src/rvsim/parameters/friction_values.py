"""Friction values of a greased RV reducer, as ``--set`` names in user units (docs/parameters.md,
"Friction"): the one place they are listed.  The built-in set ``RV-40E-bearings`` runs with them;
``rvsim.friction`` re-exports them."""

from __future__ import annotations

__all__ = ["TYPICAL_FRICTION", "TYPICAL_FRICTION_SOURCES"]

#: recommended friction values for a greased RV reducer in steady running (``--set`` names,
#: user units); every value is an estimate from the sources in TYPICAL_FRICTION_SOURCES
TYPICAL_FRICTION: dict[str, float | bool] = {
    "contact.friction_coefficient": 0.05,       # pin on disc, boundary/mixed lubrication
    "friction.pins_turn": True,                 # RV pins lie loose in housing grooves
    "friction.pin_groove_coefficient": 0.05,    # pin turning in its greased groove
    "friction.pin_rolling_coefficient": 0.001,  # rolling resistance of hardened steel
    "friction.mesh_coefficient": 0.05,          # involute flanks, mixed lubrication
    "friction.oil_viscosity": 100.0,            # mm^2/s: grease base oil at 40 C
    "friction.oil_viscosity_100": 12.1,         # mm^2/s: the same at 100 C (ISO VG 100 curve)
    "friction.arm_bearing_f0": 3.0,             # needle roller bearing, grease
    "friction.arm_bearing_f1": 0.0005,
    "friction.support_bearing_f0": 3.0,         # tapered roller bearing, grease
    "friction.support_bearing_f1": 0.0004,
}

TYPICAL_FRICTION_SOURCES: dict[str, str] = {
    "contact.friction_coefficient": "lubricated hardened steel in boundary/mixed lubrication "
    "0.03-0.1; cycloid-drive efficiency models use 0.03-0.1 (Gorla et al. 2008; Mihailidis et "
    "al. 2014; Sensinger 2013)",
    "friction.pin_groove_coefficient": "as the pin-disc pair (steel pin in a greased steel "
    "groove, sliding)",
    "friction.pin_rolling_coefficient": "rolling resistance of hardened steel on steel "
    "0.0005-0.001 (Harris & Kotzalas, Rolling Bearing Analysis, 5th ed., Ch. 13)",
    "friction.mesh_coefficient": "mean flank friction of lubricated spur gears 0.04-0.08 "
    "(ISO/TR 14179-2:2001; Niemann & Winter, Maschinenelemente II)",
    "friction.oil_viscosity": "base oil of lithium / urea greases for reducers: ISO VG 100-220 "
    "at 40 C",
    "friction.oil_viscosity_100": "estimate: ASTM D341 (Walther) line fitted to the 25 points "
    "of the ISO VG 100 curve of SKF's viscosity-temperature diagram (VI 95), digitised in "
    "JRaposo-m/SKF-Bearing-Selection-Tool (docs/production_rv40e.md section 4.4): 12.1 mm^2/s "
    "at 100 C; the grease's own data sheet (Molywhite RE No.00) was not found",
    "friction.arm_bearing_f0": "Palmgren f0 for needle roller bearings, grease: 2-4; f1 = 0.0005 "
    "(Harris & Kotzalas Ch. 13 tables after Palmgren 1959; SKF General Catalogue 4000, 1989)",
    "friction.support_bearing_f0": "Palmgren f0 for tapered roller bearings, grease: 2-4; f1 = "
    "0.0004 (same sources); catalogue friction coefficients mu = 2 M / (P d): needle 0.002-"
    "0.003, tapered 0.0017-0.0025 (Koyo/JTEKT technical section)",
}
