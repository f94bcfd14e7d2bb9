"""Lab driver (not in the wheel): how much of the excitation the surface dither is, node by node,
from the design point to high dynamic pressure, and how much room the subliminal criterion
leaves it.

    python tools/schedule/dither_margin.py [--nodes 0.4:20000,0.6:10000,0.8:5000] [--level light] \
        [--dither-scale 1,1,2,2,2] [--dither-frequency 1.7,1.7,2.9,2.9,2.3]

Per node (``bench.truth``'s two measurements, at the node instead of the nominal point):
  peaks   the closed-loop peak response to the default dither, no noise, no turbulence
          (``dither_levels``): n_z, q, p, r, n_y against the criterion (truth.dither.CRITERION:
          0.05 g, 1 deg/s, 0.02 g), and the largest share of its criterion any channel uses --
          the factor the five amplitudes could grow by within it is 1 / that share (the
          response is close to linear in the amplitude);
  ratio   RMS of the dither's part over RMS of the gusts' part of each channel in turbulence
          ``--level`` (``dither_in_turbulence``: one 30-s flight with, one without the dither,
          same gusts, seed 1): how loud the dither is against what the filters must tell it from.
--dither-scale: factors on the truth's dither amplitudes, one for all five surfaces or one
per surface (LS,RS,LF,RF,RUD): what another allocation within the criterion would give.
--dither-frequency: the five surfaces' frequencies (Hz) instead of the default lines (the
truth's own frequency rule, if any, still applies on top: truth/dither.py).
--level none: the peaks only (no turbulence flights).
"""
from __future__ import annotations

import argparse

from f16mmae.bench.truth import _DITHER_CHANNELS, dither_in_turbulence, dither_levels
from f16mmae.campaign.envelope.points import dynamic_pressure_psf
from f16mmae.truth.dither import CRITERION, DEFAULT_AMPLITUDE_DEG, DEFAULT_FREQUENCY_HZ, DitherSpec

LIMITS = {"nz_g": CRITERION["nz_g"], "q_deg_s": CRITERION["rate_deg_s"], "p_deg_s": CRITERION["rate_deg_s"],
          "r_deg_s": CRITERION["rate_deg_s"], "ny_g": CRITERION["ny_g"]}


def _five(text: str, option: str) -> list[float]:
    """One value for all five surfaces, or five (LS,RS,LF,RF,RUD)."""
    vals = [float(x) for x in text.split(",")]
    vals = vals * 5 if len(vals) == 1 else vals
    if len(vals) != 5:
        raise SystemExit(f"{option} {text}: give one value or five (LS,RS,LF,RF,RUD)")
    return vals


def scaled_dither(text: str, frequency: str | None = None) -> DitherSpec:
    """The truth's default dither with its amplitudes times ``text`` (one factor, or five
    LS,RS,LF,RF,RUD) and, if given, the five frequencies ``frequency`` (Hz)."""
    factors = _five(text, "--dither-scale")
    freq = tuple(_five(frequency, "--dither-frequency")) if frequency else DEFAULT_FREQUENCY_HZ
    return DitherSpec(amplitude_deg=tuple(a * f for a, f in zip(DEFAULT_AMPLITUDE_DEG, factors)),
                      frequency_hz=freq)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", default="0.4:20000,0.5:15000,0.6:10000,0.7:10000,0.8:5000")
    ap.add_argument("--level", default="light")
    ap.add_argument("--dither-scale", default="1")
    ap.add_argument("--dither-frequency", default=None)
    args = ap.parse_args()
    dither = scaled_dither(args.dither_scale, args.dither_frequency)
    names = [n for n, _, _ in _DITHER_CHANNELS]
    print("node | q̄ lbf/ft² | peak " + " ".join(names) + " | largest share of the criterion | "
          "RMS dither / RMS gusts " + " ".join(names))
    for item in args.nodes.split(","):
        mach, alt = (float(x) for x in item.split(":"))
        peaks = dither_levels(mach, alt, dither=dither)
        share = max(peaks[n] / LIMITS[n] for n in names)
        ratio = (dither_in_turbulence(args.level, mach=mach, alt_ft=alt, dither=dither)["ratio"]
                 if args.level != "none" else None)
        print(f"Mach {mach:.2f}, {alt:.0f} ft | {dynamic_pressure_psf(mach, alt):.0f} | "
              + " ".join(f"{peaks[n]:.3f}" for n in names) + f" | {share:.2f} | "
              + (" ".join(f"{ratio[n]:.2f}" for n in names) if ratio else "-"), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
