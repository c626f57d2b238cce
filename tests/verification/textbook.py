"""Textbook references shared by the verification tests of both engines."""

import numpy as np

from rvsim.geometry.cycloid import pin_contact_geometry


def textbook_pin_forces(reducer, crank_angle, disc, force):
    """Pin loads of a disc on rigid bearings with zero clearance: pins with a positive lever
    arm l_i carry F_i proportional to l_i**(1/0.9) (Palmgren law), the rest nothing, scaled to
    the torque of the simulated ``force`` distribution.  Returns (expected, lever)."""
    lever, _ = pin_contact_geometry(reducer, crank_angle, disc=disc)
    shape = np.where(lever > 0, np.abs(lever) ** (1 / 0.9), 0.0)
    return shape * (force @ lever) / (shape @ lever), lever
