"""What an instrument accepts: its own collision definition and its robots' motion limits.

A plan made for an instrument should pass the instrument's own check out of the box.  For
SDSS-V that check is kaiju's (``RobotGrid::robotColliders``): two robots collide when their
beta segments are closer than ``2·2.0 mm`` plus kaiju's step margin
``2·sin(ang_step)·(7.4 + 15)`` mm, 0.0782 mm at kaiju's 0.1° step (4.0782 mm in all); a
robot and a fiducial or guide camera when closer than ``2.0 + 3.0`` mm, without the margin.
Its robots are driven by jaeger at 2 RPM of the output shaft (12°/s; at most 3 RPM), each
trajectory sent with a 1 s delay before the first motion.

>>> d = collision_definition("sdss-v-apo")
>>> d.name, d.buffer_mm, round(d.margin_mm, 4), d.obstacle_margin_mm
('sdss-v kaiju', 2.0, 0.0782, 0.0)
>>> m = motion_limits("sdss-v-lco")
>>> m.rpm, m.max_rpm, m.speed_deg_s, m.start_delay_s
(2.0, 3.0, 12.0, 1.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError
from .sdss_v import INSTRUMENTS, JAEGER_COMMIT, KAIJU_COMMIT, ROBOT_BUFFER, ROUGH_ARMS

__all__ = ["CollisionDefinition", "MotionLimits", "collision_definition", "motion_limits", "KAIJU_ANG_STEP"]

#: kaiju's planning step (degrees): ``RobotGrid(stepSize=0.1)``, kaiju ``python/kaiju/robotGrid.py:106``;
#: jaeger's ``kaiju.ang_step: 0.1`` (``src/jaeger/etc/jaeger_APO.yml:75``)
KAIJU_ANG_STEP = 0.1
#: jaeger's speed of the robots' output shafts (RPM) when it runs kaiju's paths,
#: ``kaiju.speed: 2`` (``src/jaeger/etc/jaeger_APO.yml:74``, ``jaeger_LCO.yml:74``)
JAEGER_RPM = 2.0
#: the fastest output-shaft speed (RPM): kaiju's ``RobotGrid.getPathPair`` docstring, "speed: RPM at
#: output, how fast robots move, max speed is 3" (kaiju ``python/kaiju/robotGrid.py``)
MAX_RPM = 3.0
#: jaeger's delay before the first motion of a trajectory (s), ``kaiju.path_delay: 1``
#: (``src/jaeger/etc/jaeger_APO.yml:79``), passed to kaiju's ``getPathPair(pathDelay=...)``
PATH_DELAY_S = 1.0


@dataclass(frozen=True)
class CollisionDefinition:
    """An instrument's collision definition, in PROBLEM.json's terms (``collision``).

    Two robots collide when their colliding segments are closer than
    ``2·buffer_mm + margin_mm``; a robot and a fixed obstacle of buffer ``r_O`` when closer
    than ``buffer_mm + r_O + obstacle_margin_mm`` (all mm).  ``ang_step_deg`` is the planning
    step the margin stands for; ``source`` names where each number comes from.
    """

    name: str
    buffer_mm: float
    margin_mm: float
    obstacle_margin_mm: float
    ang_step_deg: float
    source: str

    def to_json(self) -> dict:
        return {"definition": self.name, "buffer_mm": self.buffer_mm, "margin_mm": self.margin_mm,
                "obstacle_margin_mm": self.obstacle_margin_mm}


@dataclass(frozen=True)
class MotionLimits:
    """How an instrument's controller runs its robots: the default and the largest joint
    speed (RPM of the output shaft: 1 RPM = 6°/s) and the delay before a trajectory's
    first motion (s)."""

    rpm: float
    max_rpm: float
    start_delay_s: float
    source: str

    @property
    def speed_deg_s(self) -> float:
        """:attr:`rpm` in degrees per second."""
        return self.rpm * 6.0

    @property
    def max_speed_deg_s(self) -> float:
        """:attr:`max_rpm` in degrees per second."""
        return self.max_rpm * 6.0


def _known(name: str) -> str:
    if name not in INSTRUMENTS:
        raise InputError(f"unknown instrument {name!r} (known: {', '.join(INSTRUMENTS)})", value=name)
    return name


def collision_definition(name: str) -> CollisionDefinition:
    """The collision definition of instrument ``name`` (module docstring).

    Parameters
    ----------
    name : str
        ``"sdss-v-apo"`` or ``"sdss-v-lco"``.

    Returns
    -------
    CollisionDefinition
        SDSS-V's is kaiju's at its 0.1° step: ``2 · 2.0 + 0.0782`` mm between robots,
        ``2.0 + 3.0`` mm to obstacles (buffers and margins in mm).

    Raises
    ------
    InputError
        An unknown instrument.

    Examples
    --------
    >>> d = collision_definition("sdss-v-apo")
    >>> d.name, d.buffer_mm, round(d.margin_mm, 4), d.obstacle_margin_mm
    ('sdss-v kaiju', 2.0, 0.0782, 0.0)

    References
    ----------
    kaiju (``sdss/kaiju``) ``src/robotGrid.cpp`` and ``python/kaiju/robotGrid.py`` at the
    commit named in ``source``; ``docs/instruments.md``.
    """
    _known(name)
    margin = 2 * math.sin(math.radians(KAIJU_ANG_STEP)) * sum(ROUGH_ARMS)
    return CollisionDefinition(
        "sdss-v kaiju", float(ROBOT_BUFFER), margin, 0.0, KAIJU_ANG_STEP,
        f"kaiju src/robotGrid.cpp:813 (buffer1 + buffer2 + maxDisplacement), :32, :13-14, "
        f"python/kaiju/robotGrid.py:106 (stepSize 0.1), :1112 (collisionBuffer 2) @{KAIJU_COMMIT}; "
        f"obstacles src/robotGrid.cpp:839,874 (no margin)")


def motion_limits(name: str) -> MotionLimits:
    """The motion limits of instrument ``name``'s controller.

    Parameters
    ----------
    name : str
        ``"sdss-v-apo"`` or ``"sdss-v-lco"``.

    Returns
    -------
    MotionLimits
        Joint speeds in RPM of the output shaft (1 RPM = 6°/s) and the start delay (s);
        SDSS-V: jaeger's 2 RPM, at most 3, 1 s delay.

    Raises
    ------
    InputError
        An unknown instrument.

    Examples
    --------
    >>> m = motion_limits("sdss-v-lco")
    >>> m.rpm, m.max_rpm, m.start_delay_s, m.speed_deg_s
    (2.0, 3.0, 1.0, 12.0)

    References
    ----------
    jaeger (``sdss/jaeger``) ``etc/jaeger_APO.yml`` and kaiju's ``getPathPair`` at the
    commits named in ``source``; ``docs/instruments.md``.
    """
    _known(name)
    return MotionLimits(JAEGER_RPM, MAX_RPM, PATH_DELAY_S,
                        f"jaeger src/jaeger/etc/jaeger_APO.yml:74,79 (kaiju.speed 2, path_delay 1) @{JAEGER_COMMIT}; "
                        f"kaiju python/kaiju/robotGrid.py getPathPair (speed: RPM at output, max speed is 3; pathDelay)")
