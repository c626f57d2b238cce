"""Small, fast studies for the integration tests (a short schedule: same physics)."""

import textwrap

import pytest

SHORT = """
[set]
"operating.duration" = 0.4
"operating.speed_ramp_time" = 0.1
"operating.load_start" = 0.1
"operating.load_ramp_end" = 0.2
"operating.steady_start" = 0.3
"""


def write_study(folder, design="L4", factors=None, extra=""):
    factors = factors or """
[factors.H]
parameter = "errors.pin_circle_radius"
levels = [0.0, 0.02]
[factors.I]
parameter = "I"
levels = [0.0, 0.03]
[factors.E]
parameter = "operating.load_torque"
levels = [100, 300]
"""
    path = folder / "study.toml"
    path.write_text(f'name = "small"\ndesign = "{design}"\n{extra}\n{SHORT}\n'
                    + textwrap.dedent(factors))
    return path


@pytest.fixture
def small_study(tmp_path):
    return write_study(tmp_path)
