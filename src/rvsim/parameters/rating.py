"""A load against the reducer's catalogue rating (``rating.*``; docs/parameters.md, "Ratings").

One function, :func:`check_torque`, used by every command and engine that takes an output
torque: above the momentary maximum torque (``rating.momentary_torque``, the catalogue's
emergency-stop figure) the load is refused; above the rated torque it returns a warning,
which the command line prints as one ``rvsim: warning: ...`` line (:func:`rvsim.cli._common.
warn`).  The engines' numbers are those of the elastic model whatever the load: a load beyond
the momentary maximum breaks or yields a real reducer, which the model cannot show.
"""

from __future__ import annotations

import math

from ..errors import ParameterError
from ..units import TO_SI

__all__ = ["check_torque", "check_rating", "check_output_speed", "peak_load",
           "contact_stress_verdict"]

#: [rad/s] per rpm
_RPM = TO_SI["rpm"]


def peak_load(reducer) -> tuple[float, str]:
    """(the largest output load of a dynamic run [N*m], the fields that set it): the load
    torque, plus the fluctuation's amplitude when ``operating.load_fluctuation`` is on."""
    op = reducer.operating
    if op.load_fluctuation and op.fluctuation_amplitude:
        return (abs(op.load_torque) + abs(op.fluctuation_amplitude),
                "operating.load_torque + operating.fluctuation_amplitude")
    return abs(op.load_torque), "operating.load_torque"


def check_rating(reducer) -> None:
    """The ratings in order: rated <= start/stop <= momentary torque, rated <= allowable
    output speed (a set whose rated torque was raised above its momentary maximum would refuse
    its own rated torque)."""
    g = reducer.rating
    if g.start_stop_torque < g.rated_torque:
        raise ParameterError("rating.start_stop_torque", f"must be at least the rated torque "
                             f"{g.rated_torque:g} N*m (got {g.start_stop_torque:g})")
    if g.momentary_torque < g.start_stop_torque:
        raise ParameterError("rating.momentary_torque", f"must be at least the start/stop "
                             f"torque {g.start_stop_torque:g} N*m (got {g.momentary_torque:g})")
    if g.allowable_output_speed < g.rated_output_speed:
        raise ParameterError("rating.allowable_output_speed", f"must be at least the rated "
                             f"output speed {g.rated_output_speed / _RPM:g} rpm (got "
                             f"{g.allowable_output_speed / _RPM:g})")


def check_torque(reducer, torque: float, field: str) -> str | None:
    """Refuse an output torque [N*m] (either sign) above the reducer's momentary maximum
    torque (ParameterError naming ``field``); return a warning text above its rated torque,
    else None.  A non-finite torque is left to the caller's own check."""
    check_rating(reducer)
    load = abs(float(torque))
    if not math.isfinite(load):
        return None
    g = reducer.rating
    if load > g.momentary_torque:
        raise ParameterError(field, f"{load:g} N*m is above the momentary maximum torque of "
                             f"{reducer.name}, {g.momentary_torque:g} N*m "
                             f"(rating.momentary_torque; rated {g.rated_torque:g} N*m)")
    if load > g.rated_torque:
        where = ("within the allowable start/stop torque" if load <= g.start_stop_torque else
                 f"above the allowable start/stop torque {g.start_stop_torque:g} N*m, a "
                 "momentary load only")
        return (f"{field}: {load:g} N*m is above the rated torque of {reducer.name}, "
                f"{g.rated_torque:g} N*m ({where}; rating.*)")
    return None


def check_output_speed(reducer, speed: float, field: str, *, refuse: bool) -> str | None:
    """An output speed [rad/s] (either sign) above the reducer's allowable output speed
    (``rating.allowable_output_speed``, the catalogue's figure at 100 % duty): refused with
    ``refuse`` (ParameterError naming ``field``: a rating life has no meaning beyond it), else
    a warning text (the model runs, as above the rated torque); None within it.  A
    non-finite speed is left to the caller's own check."""
    check_rating(reducer)
    rpm = abs(float(speed)) / _RPM
    allowed = reducer.rating.allowable_output_speed / _RPM
    if not math.isfinite(rpm) or rpm <= allowed:
        return None
    text = (f"{rpm:.4g} rpm at the output is above the allowable output speed of "
            f"{reducer.name}, {allowed:g} rpm (rating.allowable_output_speed, 100 % duty)")
    if refuse:
        raise ParameterError(field, text)
    return f"{field}: {text}"


def contact_stress_verdict(stress: float, limit: float) -> tuple[str, str | None]:
    """(verdict, warning text or None) of the largest Hertz contact stress ``stress`` [Pa]
    against the static limit ``limit`` [Pa] (``rating.static_contact_stress``, ISO 76's
    4000 MPa for line contact of hardened bearing steel; docs/parameters.md, "Ratings").
    Above it the run is still a result (not refused): permanent deformation of about 1e-4 of
    the roller diameter is ISO 76's definition of the limit.  A non-finite stress: no
    verdict ("not available", no warning)."""
    stress, limit = float(stress), float(limit)
    if not math.isfinite(stress):
        return "not available", None
    share = f"{100.0 * stress / limit:.0f} % of {limit / 1e6:g} MPa"
    if stress <= limit:
        return f"below the static limit ({share})", None
    return (f"above the static limit ({share}): permanent deformation expected",
            f"largest contact stress {stress / 1e6:.0f} MPa is above the static limit "
            f"{limit / 1e6:g} MPa (rating.static_contact_stress): permanent "
            "deformation expected")
