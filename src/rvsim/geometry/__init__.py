"""Geometry of both stages: cycloid profile and pins, involute sun-planet mesh, DXF export."""

from .cycloid import (CycloidProfile, geometric_backlash, nominal_disc_pose, pin_centres,
                      pin_gaps, profile_of, undercut_ratio)
from .involute import GearGeometry, gear_geometry

__all__ = ["CycloidProfile", "profile_of", "pin_centres", "nominal_disc_pose", "pin_gaps",
           "geometric_backlash", "undercut_ratio", "GearGeometry", "gear_geometry"]
