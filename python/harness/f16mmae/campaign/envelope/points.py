"""Flight-envelope points of the off-nominal campaign (paper Sec. VIII, Fig. 9) and q̄.

Dynamic pressure from the ISA troposphere (0 <= H <= 11 km), ``alt_ft`` geometric as JSBSim's
``position/h-sl-ft``::

    H_m   = r0 h / (r0 + h),  h = 0.3048 alt_ft   geopotential altitude, r0 = 6,356,766 m
    T     = T0 - L H_m                          T0 = 288.15 K, L = 0.0065 K/m
    p     = p0 (T / T0)^(g0 / (R L))            p0 = 2116.2166 lbf/ft^2 (101,325 Pa),
                                                g0 / (R L) = 9.80665 / (287.05287 * 0.0065)
    q̄     = (gamma / 2) p M^2                   gamma = 1.4   (= rho V^2 / 2 with V = M a)

(20,000 ft: p / p0 = 0.4599, q̄ at Mach 0.4 = 109.01 lbf/ft^2, as JSBSim's atmosphere.)

The default grid is the paper's Fig. 9, read from its points matrix: the nominal design
point NOM (Mach 0.400, 20,000 ft) and

* points 1-20, the local envelope: a checkerboard of Mach steps of 0.005 and altitude
  steps of 500 ft (a point wherever dM/0.005 + dh/500 is even), Mach 0.380-0.410 and
  19,000-22,000 ft -- the paper's "region of operability (0.03 Mach, 3000 ft)"::

        22000 ft              1           2
        21500 ft         3          4          5
        21000 ft    6          7          8          9
        20500 ft        10         11         12
        20000 ft   13         14         NOM        15
        19500 ft        16         17         18
        19000 ft             19          20
                  0.380 0.385 0.390 0.395 0.400 0.405 0.410

  As in the paper it is NOT centred on NOM: it reaches 0.020 Mach below and 0.010 above,
  2,000 ft above and 1,000 ft below (the paper stepped out until performance became
  unacceptable, so its shape is a result).  Points 9, 12, NOM, 17, 19 lie on a line of
  nearly constant q̄ (108.0-109.8 lbf/ft^2), the paper's key observation (``qline``).
* points 21-24, the extrema for longer-range trends: 25,000 ft and 15,000 ft at Mach
  0.400, Mach 0.350 and 0.450 at 20,000 ft -- each symmetric about NOM.  (The text of
  the paper's matrix puts 21 and 23 in the 0.395 column, half a step off the checkerboard;
  we put them straight above and below NOM, the pure altitude excursions pairing with the
  pure Mach excursions 22 and 24.)

The truth model trims at every one of these 25 points (checked: surface trims well
inside the limits; see ``tests/python/test_campaign_envelope.py``).

Selections (``select_points``): ``all`` (NOM + 1-24), ``local`` (NOM + 1-20),
``extrema`` (NOM + 21-24), ``qline`` (9, 12, NOM, 17, 19) or a comma list of point
numbers and ``NOM``.  Custom points (``parse_mach_alt``: ``MACH:ALT_FT,...``) are
labelled C1, C2, ...

Random points (``random:N[:seed=S]``, :func:`random_points`): a Latin hypercube of N points
over the trimmable envelope, Mach 0.3-0.8 x 5,000-35,000 ft.  Each axis is cut into N equal
strata; a seeded permutation pairs the Mach strata with the altitude strata and each point is
drawn uniformly inside its cell (``numpy.random.default_rng(S)``, S default 1), rounded to
0.0001 Mach and 1 ft and kept strictly inside the cell.  A point where the truth model does not trim is REDRAWN inside the
same cell (so the strata stay covered), up to 20 times, then the selection is refused naming
the cell.  Labelled R1..RN in order of Mach, group ``random``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import F16mmaeError
from ...names import DESIGN_ALT_FT, DESIGN_MACH
from ...truth.aircraft import ALT_FT_RANGE, MACH_RANGE, check_flight_condition
from ..engine.config import CampaignError
from ..engine.points import check_points

#: ISA sea-level pressure (lbf/ft^2), temperature (K), lapse rate (K/m) and g0/(R L).
P0_PSF = 101_325.0 / 47.880258889  # 2116.2166 lbf/ft^2
T0_K = 288.15
LAPSE_K_PER_M = 0.0065
PRESSURE_EXPONENT = 9.80665 / (287.05287 * LAPSE_K_PER_M)
EARTH_RADIUS_M = 6_356_766.0
TROPOPAUSE_FT = 11_000.0 * EARTH_RADIUS_M / (EARTH_RADIUS_M - 11_000.0) / 0.3048
GAMMA_AIR = 1.4

NOMINAL_LABEL = "NOM"
SELECTIONS = ("all", "local", "extrema", "qline")


class EnvelopeError(F16mmaeError, ValueError):
    """A point selection or a custom point is invalid; the message names it and the valid choices."""


def pressure_psf(alt_ft: float) -> float:
    """ISA static pressure (lbf/ft^2) at pressure altitude ``alt_ft`` in the troposphere."""
    if not 0.0 <= alt_ft <= TROPOPAUSE_FT:
        raise EnvelopeError(f"altitude {alt_ft} ft outside the ISA troposphere 0-{TROPOPAUSE_FT:.0f} ft")
    h_m = 0.3048 * alt_ft
    t_k = T0_K - LAPSE_K_PER_M * EARTH_RADIUS_M * h_m / (EARTH_RADIUS_M + h_m)
    return P0_PSF * (t_k / T0_K) ** PRESSURE_EXPONENT


def dynamic_pressure_psf(mach: float, alt_ft: float) -> float:
    """q̄ = (gamma/2) p M^2 (lbf/ft^2) in the ISA, see the module docstring."""
    return 0.5 * GAMMA_AIR * pressure_psf(alt_ft) * mach * mach


@dataclass(frozen=True)
class EnvelopePoint:
    """One flight condition: ``label`` ("NOM", "1".."24", "C1"... or "R1"...), Mach, altitude
    (ft) and ``group`` ("nominal" | "local" | "extrema" | "custom" | "random")."""

    label: str
    mach: float
    alt_ft: float
    group: str

    @property
    def qbar_psf(self) -> float:
        return dynamic_pressure_psf(self.mach, self.alt_ft)

    def to_dict(self) -> dict:
        return {"label": self.label, "mach": self.mach, "alt_ft": self.alt_ft,
                "group": self.group, "qbar_psf": round(self.qbar_psf, 3)}


_LOCAL = (  # (number, Mach, alt_ft) read from the paper's Fig. 9
    (1, 0.390, 22000), (2, 0.400, 22000),
    (3, 0.385, 21500), (4, 0.395, 21500), (5, 0.405, 21500),
    (6, 0.380, 21000), (7, 0.390, 21000), (8, 0.400, 21000), (9, 0.410, 21000),
    (10, 0.385, 20500), (11, 0.395, 20500), (12, 0.405, 20500),
    (13, 0.380, 20000), (14, 0.390, 20000), (15, 0.410, 20000),
    (16, 0.385, 19500), (17, 0.395, 19500), (18, 0.405, 19500),
    (19, 0.390, 19000), (20, 0.400, 19000),
)
_EXTREMA = ((21, 0.400, 25000), (22, 0.350, 20000), (23, 0.400, 15000), (24, 0.450, 20000))

NOMINAL = EnvelopePoint(NOMINAL_LABEL, DESIGN_MACH, DESIGN_ALT_FT, "nominal")
#: The paper's 25 points: NOM, then 1-24 in order.
PAPER_POINTS: tuple[EnvelopePoint, ...] = (NOMINAL,) + tuple(
    EnvelopePoint(str(n), m, float(h), "local") for n, m, h in _LOCAL) + tuple(
    EnvelopePoint(str(n), m, float(h), "extrema") for n, m, h in _EXTREMA)
_BY_LABEL = {p.label: p for p in PAPER_POINTS}
#: The paper's axis of nearly constant dynamic pressure through NOM.
QLINE_LABELS = ("9", "12", NOMINAL_LABEL, "17", "19")


RANDOM_FORM = "random:N[:seed=S] (N 1-1000, S >= 1)"
#: Redraws of a random point inside its cell before the selection is refused.
RANDOM_REDRAWS = 20


def parse_random(text: str) -> tuple[int, int]:
    """``random:N[:seed=S]`` -> (N, S); EnvelopeError naming the token and the form."""
    parts = text.strip().split(":")
    try:
        if parts[0].lower() != "random" or len(parts) not in (2, 3):
            raise ValueError
        n = int(parts[1])
        seed = 1
        if len(parts) == 3:
            key, eq, val = parts[2].partition("=")
            if key.strip().lower() != "seed" or not eq:
                raise ValueError
            seed = int(val)
    except ValueError:
        raise EnvelopeError(f"--points {text!r} is not {RANDOM_FORM}") from None
    if not 1 <= n <= 1000 or seed < 1:
        raise EnvelopeError(f"--points {text!r}: need {RANDOM_FORM}")
    return n, seed


def _trims(mach: float, alt_ft: float) -> bool:
    from ...truth.aircraft import TrimError, trimmed_fdm
    try:
        trimmed_fdm(mach, alt_ft)
    except TrimError:
        return False
    return True


def _inside(low: float, width: float, cell: int, u: float, unit: float) -> float:
    """A uniform draw ``u`` in cell ``cell`` of ``width``, kept a rounding ``unit`` off its
    edges, so the value rounded to ``unit`` stays strictly inside its cell."""
    return low + width * cell + unit + (width - 2.0 * unit) * u


def random_points(n: int, seed: int = 1, trims=_trims) -> tuple[EnvelopePoint, ...]:
    """N Latin-hypercube points over the envelope (module docstring); ``trims(mach, alt_ft)``
    says whether the truth model trims there (default: JSBSim's trim of the derived F-16)."""
    rng = np.random.default_rng(seed)
    pair = rng.permutation(n)
    (m0, m1), (h0, h1) = MACH_RANGE, ALT_FT_RANGE
    out = []
    for i in range(n):
        for _ in range(RANDOM_REDRAWS):
            a, b = rng.random(2)
            mach = round(float(_inside(m0, (m1 - m0) / n, i, a, 1e-4)), 4)
            alt = float(round(_inside(h0, (h1 - h0) / n, pair[i], b, 1.0)))
            if trims(mach, alt):
                break
        else:
            raise EnvelopeError(
                f"random point {i + 1} of {n} (seed {seed}): no trim in {RANDOM_REDRAWS} draws inside its cell "
                f"Mach {m0 + (m1 - m0) * i / n:.3f}-{m0 + (m1 - m0) * (i + 1) / n:.3f} x "
                f"{h0 + (h1 - h0) * pair[i] / n:.0f}-{h0 + (h1 - h0) * (pair[i] + 1) / n:.0f} ft")
        out.append(EnvelopePoint(f"R{i + 1}", mach, alt, "random"))
    return tuple(out)


def select_points(text: str) -> tuple[EnvelopePoint, ...]:
    """Paper points from a selection name or a comma list of numbers / NOM (module docstring),
    in the paper's order (NOM first), or ``random:N[:seed=S]`` random points."""
    t = text.strip().lower()
    if t.startswith("random"):
        return random_points(*parse_random(text))
    if t == "all":
        return PAPER_POINTS
    if t == "local":
        return tuple(p for p in PAPER_POINTS if p.group in ("nominal", "local"))
    if t == "extrema":
        return tuple(p for p in PAPER_POINTS if p.group in ("nominal", "extrema"))
    if t == "qline":
        return tuple(p for p in PAPER_POINTS if p.label in QLINE_LABELS)
    items = [s.strip().upper() for s in text.split(",") if s.strip()]
    bad = [s for s in items if s not in _BY_LABEL]
    if bad or not items:
        raise EnvelopeError(
            f"--points: unknown point(s) {', '.join(bad) or repr(text)}; valid: "
            f"{' | '.join(SELECTIONS)}, a comma list of 1-24 and NOM, or {RANDOM_FORM}")
    if len(set(items)) != len(items):
        raise EnvelopeError(f"--points {text!r} lists a point twice")
    chosen = set(items)
    return tuple(p for p in PAPER_POINTS if p.label in chosen)


def parse_mach_alt(text: str) -> tuple[EnvelopePoint, ...]:
    """Custom points ``MACH:ALT_FT,...`` (e.g. ``0.42:21000,0.38:19000``), labelled C1, C2, ..."""
    out = []
    items = [s.strip() for s in text.split(",") if s.strip()]
    if not items:
        raise EnvelopeError(f"--mach-alt {text!r} holds no point; expected MACH:ALT_FT[,MACH:ALT_FT...]")
    for i, item in enumerate(items, 1):
        parts = item.split(":")
        try:
            if len(parts) != 2:
                raise ValueError
            mach, alt_ft = float(parts[0]), float(parts[1])
        except ValueError:
            raise EnvelopeError(f"--mach-alt item {item!r} is not MACH:ALT_FT (e.g. 0.42:21000)") from None
        try:
            check_flight_condition(mach, alt_ft)
        except ValueError as exc:
            raise EnvelopeError(f"--mach-alt item {item!r}: {exc}") from None
        out.append(EnvelopePoint(f"C{i}", mach, alt_ft, "custom"))
    return tuple(out)


def check_distinct(points) -> None:
    """Refuse an empty list, a label used twice, one flight condition listed twice or a point
    outside the envelope (``engine.points.check_points``), as an EnvelopeError."""
    try:
        check_points(points)
    except CampaignError as exc:
        raise EnvelopeError(str(exc)) from None
