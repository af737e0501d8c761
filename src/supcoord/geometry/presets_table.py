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
| ``spec-s5`` | 6.2 (source) | 1.788 / 1.788 (assumed: DESI's × 6.2/10.4) | [0, 180] (assumed) | 0.298 (assumed: DESI's × 6.2/10.4) |
| ``must`` | 6.2 (source) | 1.788 / 1.788 (assumed: DESI's × 6.2/10.4) | [0, 180] (assumed) | 0.298 (assumed: DESI's × 6.2/10.4) |
| ``wst`` | 7.0 (source, "~7 mm") | 2.019 / 2.019 (assumed: DESI's × 7.0/10.4) | [0, 180] (assumed) | 0.337 (assumed: DESI's × 7.0/10.4) |

The next-generation focal planes publish their robot count and pitch, not their arms: their
arms and buffer are DESI's scaled by the pitch ratio (the same arms-to-pitch proportion as
DESI's positioners, which the 6.2 mm prototypes shrink).  :attr:`Preset.rings` is the hex grid
nearest to the published count (``1 + 3R(R+1)`` robots): Spec-S5 12,852 per focal plane →
65 rings, 12,871 robots (+19); MUST "more than 20,000" → 82 rings, 20,419 (81 rings give
19,927, fewer than published); WST 32,000 → 103 rings, 32,137 (+137).

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
- Spec-S5: spec-s5.org, Instrument overview (two 6 m telescopes, 12,852 fibre robots per
  telescope); the 6.2 mm pitch of the Stage-5 prototypes: arXiv:2508.19711 (Prototyping of
  6.2-mm-Pitch Fiber Positioner Modules for Stage-V Telescope Instrumentation),
  arXiv:2606.18909 (a Trillium-based 21-positioner module), arXiv:2606.18915 (a 15-positioner
  MPS module).
- MUST: Z. Cai et al., Sci. China Phys. Mech. Astron. 68(9) (2025), doi:10.1007/s11433-025-2725-3
  (6.5 m, more than 20,000 fibres, 6.2 mm pitch robots, modular focal plane).
- WST: wstelescope.eu, Instruments (32,000 MOS fibres, ~7 mm centre to centre);
  S. Pernecker et al., arXiv:2606.18957 (WST MOS Fiber Positioners: Development of a
  32,000-Unit Precision Robotic System).
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
    #: rings of the hex grid nearest the published robot count (``None``: not a full focal plane)
    rings: int | None = None


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
    "spec-s5": Preset("spec-s5", 6.2, 1.788, 1.788, (0.0, 180.0), 0.298, "12,852 per focal plane",
                      "Spec-S5 (spec-s5.org: 12,852 robots per telescope; 6.2 mm pitch of the Stage-5 "
                      "prototypes, arXiv:2508.19711); arms and buffer assumed: scaled from DESI's by pitch ratio "
                      "6.2/10.4; beta range assumed; 65 rings = 12,871 robots, the nearest hex count; see "
                      "docs/references.md", rings=65),
    "must": Preset("must", 6.2, 1.788, 1.788, (0.0, 180.0), 0.298, ">20,000",
                   "MUST (Cai et al. 2025, doi:10.1007/s11433-025-2725-3: more than 20,000 fibres, 6.2 mm pitch); "
                   "arms and buffer assumed: scaled from DESI's by pitch ratio 6.2/10.4; beta range assumed; "
                   "82 rings = 20,419 robots, the nearest hex count above 20,000; see docs/references.md",
                   rings=82),
    "wst": Preset("wst", 7.0, 2.019, 2.019, (0.0, 180.0), 0.337, "32,000",
                  "WST (wstelescope.eu; Pernecker et al., arXiv:2606.18957: 32,000 units, ~7 mm centre to centre); "
                  "arms and buffer assumed: scaled from DESI's by pitch ratio 7.0/10.4; beta range assumed; "
                  "103 rings = 32,137 robots, the nearest hex count; see docs/references.md", rings=103),
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
