"""Textbook references shared by the verification tests of both engines and both topologies."""

import math

import numpy as np

from rvsim.geometry.cycloid import nominal_disc_pose, pin_contact_geometry
from rvsim.geometry.layout import output_pins


def textbook_share(lever, force):
    """Contacts on rigid bearings with zero clearance: the contacts with a positive lever arm
    l_i (d approach / d relative rotation) carry F_i proportional to l_i**(1/0.9) (Palmgren
    law), the rest nothing, scaled to the torque of the computed ``force`` distribution."""
    shape = np.where(lever > 0, np.abs(lever) ** (1 / 0.9), 0.0)
    return shape * (force @ lever) / (shape @ lever)


def textbook_pin_forces(reducer, crank_angle, disc, force):
    """Ring pin loads of a disc (:func:`textbook_share`).  Returns (expected, lever)."""
    lever, _ = pin_contact_geometry(reducer, crank_angle, disc=disc)
    return textbook_share(lever, force), lever


def output_pin_levers(reducer, crank_angle, disc):
    """Single-stage drive, nominal pose: lever arm of each output pin, the growth of its
    approach to the hole wall per radian the disc turns ahead of the output flange."""
    x, y, angle = nominal_disc_pose(reducer, crank_angle, disc)
    pins = output_pins(reducer)
    c, s = math.cos(angle), math.sin(angle)
    px, py = c * pins[:, 0] - s * pins[:, 1], s * pins[:, 0] + c * pins[:, 1]
    rx, ry = -x, -y                      # pin centre minus hole centre (flange = disc angle)
    dist = math.hypot(rx, ry)
    nx, ny = rx / dist, ry / dist
    return nx * py - ny * px


def textbook_output_pin_forces(reducer, crank_angle, disc, force):
    """Output pin loads of a disc (:func:`textbook_share`).  Returns (expected, lever)."""
    lever = output_pin_levers(reducer, crank_angle, disc)
    return textbook_share(lever, force), lever
