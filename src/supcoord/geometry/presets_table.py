"""Instrument presets: pitch, arm lengths, beta range, buffer of real focal planes.

Numbers come from the instruments' publications and software (``docs/references.md``
gives the source of each) and are marked ``source``; numbers no source gives are marked
``assumed`` and are parameters of :func:`supcoord.problems.presets.preset_problem`.

| preset | pitch (mm) | alpha / beta (mm) | beta range (°) | buffer (mm) |
|---|---|---|---|---|
| ``sdss-v`` | 22.4 (source) | 7.4 / 15.0 (source) | [0, 180] (assumed) | 2.0 (source) |
| ``desi`` | 10.4 (source) | 3.0 / 3.0 (source, "~3 mm", patrol ~6 mm) | [0, 180] (assumed) | 0.5 (assumed) |
| ``moons`` | none: a parameter (not in our sources) | 8.0 / 17.0 (source) | [−180, 150] (source) | 2.0 (from the 4 mm minimum fibre approach) |
| ``pfs`` | 8.0 (source) | 2.4 / 2.4 (source, "~2.4 mm") | [0, 180] (assumed) | 0.5 (assumed) |

SDSS-V robots park in a *folded lattice* at ``(α, β) = (10°, 170°)`` (kaiju);
:func:`folded_position` gives the nearest discrete position, and
:func:`supcoord.problems.presets.preset_problem` (``start="folded"``) starts every robot
there.

References
----------
Full citations, with DOIs where they exist: ``docs/references.md``.

- SDSS-V: C. Sayres et al., SDSS-V Algorithms: Fast, Collision-free Trajectory Planning
  for Heavily Overlapping Robotic Fiber Positioners, AJ 161, 92 (2021) (kaiju, the folded
  lattice); kaiju's ``RobotGrid`` (2.0 mm beta-arm buffer); SDSS-V FPS calibrations
  (``sdss/fps_calibrations``: 22.4 mm hole spacing, measured alpha arms 7.3–7.5 mm).
- DESI: J. H. Silber et al., The Robotic Multiobject Focal Plane System of DESI, AJ 165, 9
  (2023) (5020 robots, 10.4 mm pitch); DESI Collaboration, The DESI Experiment Part II:
  Instrument Design (2016).
- MOONS: M. Cirasuolo et al., Proc. SPIE 9147 (2014) (~1000 fibres); the MOONS fibre
  positioner software's prototype parameters (α 8 mm, β 17 mm, β ∈ [−180°, 150°], 4 mm
  closest fibre approach).
- Subaru PFS: H. Sugai et al., JATIS 1(3), 035001 (2015) (2394 fibres); PFS
  instrumentation pages (Cobra positioners, 8 mm pitch, 9.5 mm patrol diameter).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError
from .kinematics import AlphaBeta

__all__ = ["Preset", "PRESETS", "preset_kinematics", "folded_position", "get_preset"]


@dataclass(frozen=True)
class Preset:
    """An instrument's geometry; ``pitch=None`` means "not in our sources, pass one"."""

    name: str
    pitch: float | None
    alpha: float
    beta: float
    beta_range: tuple[float, float]
    buffer: float
    positioners: str
    source: str


PRESETS: dict[str, Preset] = {
    "sdss-v": Preset("sdss-v", 22.4, 7.4, 15.0, (0.0, 180.0), 2.0, "~500 per telescope",
                     "SDSS-V robots (Sayres et al. 2021; kaiju; sdss/fps_calibrations): 22.4 mm hex, "
                     "alpha 7.4, beta 15, buffer 2.0 around the beta arm; beta range [0, 180] assumed; "
                     "see docs/references.md"),
    "desi": Preset("desi", 10.4, 3.0, 3.0, (0.0, 180.0), 0.5, "5020",
                   "DESI focal plane (Silber et al. 2023): 10.4 mm pitch, ~3/3 mm arms (patrol radius "
                   "~6 mm); beta range and buffer 0.5 mm assumed; see docs/references.md"),
    "moons": Preset("moons", None, 8.0, 17.0, (-180.0, 150.0), 2.0, "~1000",
                    "MOONS (Cirasuolo et al. 2014; MOONS fibre positioner software): alpha 8, beta 17, "
                    "beta in [-180, 150], min fibre approach 4 mm (buffer 2.0 each); pitch not in these "
                    "sources; see docs/references.md"),
    "pfs": Preset("pfs", 8.0, 2.4, 2.4, (0.0, 180.0), 0.5, "2394",
                  "Subaru PFS Cobra (Sugai et al. 2015; PFS instrumentation): 8 mm pitch, ~2.4/2.4 mm "
                  "arms; beta range and buffer 0.5 mm assumed; see docs/references.md"),
}


def get_preset(name: str) -> Preset:
    """The preset called ``name`` (case-insensitive); an unknown name is an :class:`InputError`."""
    key = str(name).lower()
    if key not in PRESETS:
        raise InputError(f"unknown preset {name!r} (known: {', '.join(PRESETS)})", value=name)
    return PRESETS[key]


def preset_kinematics(name: str, alpha_steps: int = 36, beta_steps: int = 19) -> AlphaBeta:
    """The preset's alpha-beta kinematics discretised into ``alpha_steps × beta_steps`` positions."""
    p = get_preset(name)
    return AlphaBeta(p.alpha, p.beta, alpha_steps, beta_steps, p.beta_range)


def folded_position(kin: AlphaBeta, alpha_deg: float = 10.0, beta_deg: float = 170.0) -> tuple[int, int]:
    """The discrete position nearest to ``(α, β)`` (default: SDSS-V's folded lattice).

    >>> folded_position(AlphaBeta(7.4, 15.0, 36, 19, (0, 180)))
    (1, 17)
    """
    i = int(round(alpha_deg / 360.0 * kin.alpha_steps)) % kin.alpha_steps
    lo, hi = kin.beta_range
    j = int(round((beta_deg - lo) / (hi - lo) * (kin.beta_steps - 1)))
    return i, min(max(j, 0), kin.beta_steps - 1)
