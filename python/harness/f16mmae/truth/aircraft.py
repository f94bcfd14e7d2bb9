"""The derived JSBSim F-16: stock airframe, our flight-control section, direct surface access.

JSBSim's stock ``f16`` (aerodynamics, propulsion, mass) is read at run time from the installed
``jsbsim`` package; its ``<flight_control>``, ``<system>``, ``<external_reactions>`` and
``<output>`` sections are replaced by a pure MIXER, its ``<ground_reactions>`` emptied of their
contact points (see below), and the result is written into a content-addressed cache root (``$F16MMAE_CACHE_DIR``, default
``~/.cache/f16mmae``), shared by every process and never stale (no JSBSim aircraft data lives in
this repo).

The stock aerodynamics read four control properties only.  The mixer computes them from the
five surface POSITIONS ``delta = (LS, RS, LF, RF, RUD)`` (rad, trailing edge down positive for
stabilators and flaperons, trailing edge left positive for the rudder), which Python writes
into ``SURFACE_PROPERTIES`` (the actuators live in Python, ``f16mmae.truth.actuators``)::

    fcs/elevator-pos-rad  = (LS + RS)/2                       + E_MAX * (elevator + pitch-trim cmd)
    fcs/aileron-pos-rad   = (LF - RF)/2 + k (LS - RS)/2       + A_MAX * (aileron + roll-trim cmd)
    fcs/flaperon-mix-rad  =  LF + RF
    fcs/rudder-pos-rad    =  RUD                              + R_MAX * (rudder + yaw-trim cmd)

i.e. ``v = MIXING @ delta`` (``actuators.MIXING``, k = ``actuators.DIFFERENTIAL_TAIL_ROLL_SHARE``).
Positive ``fcs/aileron-pos-rad`` rolls right in the stock tables, so a left flaperon (or left
stabilator) trailing edge down rolls right.  The pilot ``*-cmd-norm`` terms exist only for
JSBSim's trim routine (FGTrim drives them); :func:`trim` folds them into the surface positions
and zeroes them, so after trimming the aircraft is flown by the five positions alone; the
trimmed state is then stored as the initial condition, so ``run_ic()`` returns to the trim
(and perturbing ``ic/*`` + ``run_ic()`` linearizes about it).

The leading-edge flap is held at the stock schedule's value for the trimmed angle of attack
(0.262 rad above 5 deg alpha, 0.436 rad above 15 deg, -0.0349 rad above Mach 0.9, else 0);
the speed brake is retracted and the gear up.  Throttle: ``fcs/throttle-pos-norm =
2 * fcs/throttle-cmd-norm`` as in the stock FCS (above 1 = afterburner), held at trim.

No contact points (``contacts=False``, the default): the stock gear (three retracted bogeys)
and seven structure points touch nothing in flight, so their forces and moments are exactly
zero, yet JSBSim computes the ground under each of the ten points at every step (geodetic
conversions, a fifth of its stepping).  Without them the aircraft flies bit for bit the same
flights (tests/python/test_truth_aircraft.py flies both) and cannot land or touch the
ground: the flights here start at 5,000 ft or more and last seconds to hours of level flight.
``contacts=True`` keeps the stock contact points (for that comparison).
"""
from __future__ import annotations

import hashlib
import math
import os
import shutil
import tempfile
import threading
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import jsbsim
import numpy as np

from ..cache import cache_root
from ..errors import F16mmaeError
from ..names import ACTUATORS, SIM_RATE_HZ
from . import actuators, sensors, turbulence
from . import engine as engine_module

#: Name of the derived aircraft inside the temporary root.
AIRCRAFT_NAME = "f16mmae_f16"
#: Properties holding the five surface positions (rad), order ``names.ACTUATORS``.
SURFACE_PROPERTIES: tuple[str, ...] = tuple(f"fcs/{a.lower()}-pos-rad" for a in ACTUATORS)
#: The four stock aerodynamic control properties the mixer writes (rows of ``MIXING``).
AERO_CONTROL_PROPERTIES: tuple[str, ...] = (
    "fcs/elevator-pos-rad", "fcs/aileron-pos-rad", "fcs/flaperon-mix-rad", "fcs/rudder-pos-rad",
)
#: 1 while the mixer computes the pilot command terms (JSBSim's trim drives them, and its
#: linearization, ``design.linearize.jsbsim_linearization``, perturbs them), 0 in flight:
#: :func:`trim` folds the commands into the surfaces, zeroes them and then switches their
#: channel off, so their terms hold the exact zeros they last computed instead of recomputing
#: them at every step.
TRIM_COMMANDS_PROPERTY = "fcs/f16mmae/trim-commands"
#: Flight envelope in which trim is offered (the issue's envelope).
MACH_RANGE = (0.3, 0.8)
ALT_FT_RANGE = (5_000.0, 35_000.0)

_lock = threading.Lock()
_root_dirs: dict[bool, str] = {}  # contacts -> the derived root written for it


class TrimError(F16mmaeError, RuntimeError):
    """JSBSim could not trim the aircraft at the requested flight condition."""


@dataclass(frozen=True)
class TrimPoint:
    """A trimmed level-flight condition of the derived aircraft.

    u_rad (5,): surface deflections LS RS LF RF RUD (rad); z (7,): noise-free measurements
    (``sensors.ideal``, units of ``names.SENSOR_UNITS``); throttle: ``fcs/throttle-cmd-norm``;
    vt_fps true airspeed; alpha_rad, theta_rad; mach; alt_ft; lef_rad leading-edge flap;
    qbar_psf dynamic pressure; weight_lbs.
    """

    u_rad: np.ndarray
    z: np.ndarray
    throttle: float
    vt_fps: float
    alpha_rad: float
    theta_rad: float
    mach: float
    alt_ft: float
    lef_rad: float
    qbar_psf: float
    weight_lbs: float


def _flight_control_xml() -> str:
    """Our ``<flight_control>``: declares the five surface positions and mixes them (module
    docstring).  Each summer adds its terms in the order of the MIXING rows, the pilot command
    terms last; a term of gain 1 enters the summer directly (``1.0 * x == x`` exactly), any other
    through its own ``<pure_gain>``.  The pilot command terms are computed in the channel
    "Trim commands", which runs only while ``TRIM_COMMANDS_PROPERTY`` is 1 (see :func:`trim`)."""
    k = actuators.DIFFERENTIAL_TAIL_ROLL_SHARE
    e_max, a_max, r_max = actuators.TRIM_COMMAND_SCALE_RAD
    decl = "\n".join(f'  <property value="0">{p}</property>' for p in SURFACE_PROPERTIES)
    ls, rs, lf, rf, rud = SURFACE_PROPERTIES
    trim_gains: list[str] = []

    def summer(name: str, terms: list[tuple[str, float]], commands: list[tuple[str, float]], output: str) -> str:
        parts, inputs = [], []
        for i, (prop, gain) in enumerate(terms + commands):
            if gain == 1.0:
                inputs.append(f"<input>{prop}</input>")
                continue
            tmp = f"fcs/f16mmae/{name}-term{i}"
            gain_xml = f'  <pure_gain name="{tmp}"><input>{prop}</input><gain>{gain!r}</gain></pure_gain>'
            (trim_gains if i >= len(terms) else parts).append(gain_xml)
            inputs.append(f"<input>{tmp}</input>")
        parts.append(f'  <summer name="fcs/f16mmae/{name}">{"".join(inputs)}'
                     f"<output>{output}</output></summer>")
        return "\n".join(parts)

    body = "\n".join([
        summer("elevator", [(ls, 0.5), (rs, 0.5)],
               [("fcs/elevator-cmd-norm", e_max), ("fcs/pitch-trim-cmd-norm", e_max)], "fcs/elevator-pos-rad"),
        summer("aileron", [(lf, 0.5), (rf, -0.5), (ls, 0.5 * k), (rs, -0.5 * k)],
               [("fcs/aileron-cmd-norm", a_max), ("fcs/roll-trim-cmd-norm", a_max)], "fcs/aileron-pos-rad"),
        summer("flaperon", [(lf, 1.0), (rf, 1.0)], [], "fcs/flaperon-mix-rad"),
        summer("rudder", [(rud, 1.0)],
               [("fcs/rudder-cmd-norm", r_max), ("fcs/yaw-trim-cmd-norm", r_max)], "fcs/rudder-pos-rad"),
        '  <pure_gain name="fcs/f16mmae/throttle"><input>fcs/throttle-cmd-norm</input>'
        "<gain>2</gain><output>fcs/throttle-pos-norm</output></pure_gain>",
    ])
    trim_body = "\n".join(trim_gains)
    return (f'<flight_control name="f16mmae mixer">\n{decl}\n'
            '  <property value="0">fcs/lef-pos-rad</property>\n'
            f'  <property value="1">{TRIM_COMMANDS_PROPERTY}</property>\n'
            f'  <channel name="Trim commands" execute="{TRIM_COMMANDS_PROPERTY}">\n{trim_body}\n  </channel>\n'
            f'  <channel name="Mixer">\n{body}\n  </channel>\n</flight_control>')


def _cache_base() -> str:
    return str(cache_root())


def derived_root(contacts: bool = False) -> str:
    """Directory holding the derived aircraft (with the stock contact points if ``contacts``).

    Its name carries the SHA-256 of the derived XML (which includes the installed jsbsim's
    f16.xml), so a root is written once, atomically (temporary directory + rename), and reused
    by every later process: no per-process temporary directories to leak from pool workers.
    """
    with _lock:
        known = _root_dirs.get(contacts)
        if known is not None and os.path.isdir(known):
            return known
        src = os.path.join(jsbsim.get_default_root_dir(), "aircraft", "f16", "f16.xml")
        tree = ET.parse(src)
        cfg = tree.getroot()
        for tag in ("system", "external_reactions", "output", "flight_control"):
            for el in cfg.findall(tag):
                cfg.remove(el)
        if not contacts:  # JSBSim needs the element, not its contacts
            for el in cfg.findall("ground_reactions"):
                for contact in el.findall("contact"):
                    el.remove(contact)
        cfg.set("name", "F-16 (JSBSim f16 airframe, f16mmae flight control)")
        aero = cfg.find("aerodynamics")
        cfg.insert(list(cfg).index(aero), ET.fromstring(_flight_control_xml()))
        xml = ET.tostring(cfg, encoding="utf-8")
        base = _cache_base()
        root = os.path.join(base, "aircraft-" + hashlib.sha256(xml).hexdigest()[:16])
        if not os.path.isfile(os.path.join(root, "aircraft", AIRCRAFT_NAME, f"{AIRCRAFT_NAME}.xml")):
            os.makedirs(base, exist_ok=True)
            staging = tempfile.mkdtemp(prefix=".aircraft-", dir=base)
            os.makedirs(os.path.join(staging, "aircraft", AIRCRAFT_NAME))
            with open(os.path.join(staging, "aircraft", AIRCRAFT_NAME, f"{AIRCRAFT_NAME}.xml"), "wb") as f:
                f.write(b'<?xml version="1.0"?>\n' + xml)
            try:
                os.rename(staging, root)
            except OSError:  # another process got there first: theirs is identical
                shutil.rmtree(staging, ignore_errors=True)
        _root_dirs[contacts] = root
        return root


def load_fdm(seed: int = 1, dt_s: float = 1.0 / SIM_RATE_HZ, stock: bool = False,
             cxx: bool = False, contacts: bool = False) -> jsbsim.FGFDMExec:
    """A loaded, untrimmed FGFDMExec of the derived aircraft (or the stock ``f16``); with
    ``contacts`` the derived aircraft keeps the stock contact points (module docstring).

    seed >= 1 seeds JSBSim's random generators (turbulence); dt_s is the integration step (s).
    cxx: an ``f16mmae.core.JSBSimExec`` (the same JSBSim library, made and stepped from C++,
    with ``reset_winds`` for :func:`restart`) instead of a ``jsbsim.FGFDMExec``.
    """
    if int(seed) < 1:
        raise ValueError(f"seed must be >= 1 (JSBSim maps 0 to 1), got {seed}")
    os.environ.setdefault("JSBSIM_DEBUG", "0")  # no start-up banner
    pkg = jsbsim.get_default_root_dir()
    root = pkg if stock else derived_root(contacts)
    fdm = engine_module.jsbsim_exec(root) if cxx else jsbsim.FGFDMExec(root, None)
    fdm.set_debug_level(0)
    fdm.set_engine_path(os.path.join(pkg, "engine"))
    fdm.set_systems_path(os.path.join(pkg, "systems"))
    fdm["simulation/randomseed"] = int(seed)
    fdm["atmosphere/randomseed"] = int(seed)
    if not fdm.load_model("f16" if stock else AIRCRAFT_NAME):
        raise RuntimeError("JSBSim failed to load the F-16 model")
    fdm.set_dt(dt_s)
    return fdm


#: The leading-edge flap's positions (rad) below Mach 0.9, and the trim alphas (rad) above
#: which it takes the next one (:func:`lef_schedule_rad`; the scheduled design's
#: configuration layers, design/schedule.py).
LEF_POSITIONS_RAD: tuple[float, ...] = (0.0, 0.262, 0.436)
LEF_ALPHA_SWITCH_RAD: tuple[float, ...] = (0.0873, 0.2618)


def lef_schedule_rad(alpha_rad: float, mach: float) -> float:
    """Leading-edge flap (rad) from the stock F-16 FCS schedule, gear up, in flight."""
    if mach > 0.9:
        return -0.0349
    return LEF_POSITIONS_RAD[sum(alpha_rad > a for a in LEF_ALPHA_SWITCH_RAD)]


def check_flight_condition(mach: float, alt_ft: float) -> None:
    """Raise ValueError unless (mach, alt_ft) lies in the supported envelope."""
    if not (MACH_RANGE[0] <= mach <= MACH_RANGE[1]) or not math.isfinite(mach):
        raise ValueError(f"mach {mach} outside the supported range {MACH_RANGE[0]}-{MACH_RANGE[1]}")
    if not (ALT_FT_RANGE[0] <= alt_ft <= ALT_FT_RANGE[1]) or not math.isfinite(alt_ft):
        raise ValueError(f"alt_ft {alt_ft} outside the supported range "
                         f"{ALT_FT_RANGE[0]:.0f}-{ALT_FT_RANGE[1]:.0f} ft")


def set_surfaces(fdm: jsbsim.FGFDMExec, u_rad) -> None:
    """Write the five surface positions (rad, order LS RS LF RF RUD); the mixer applies them
    at the next ``run()`` / ``run_ic()``.  No actuator dynamics."""
    for prop, val in zip(SURFACE_PROPERTIES, u_rad, strict=True):
        fdm[prop] = float(val)


def get_surfaces(fdm: jsbsim.FGFDMExec) -> np.ndarray:
    """The five surface positions (rad) currently written."""
    return np.array([fdm[p] for p in SURFACE_PROPERTIES])


def trim(fdm: jsbsim.FGFDMExec, mach: float, alt_ft: float, lef_rad: float | None = None,
         gamma_deg: float = 0.0) -> TrimPoint:
    """Trim ``fdm`` (a derived aircraft from :func:`load_fdm`) in wings-level, straight, level
    flight at (mach, alt_ft) with JSBSim's full trim (a steady climb or descent at flight-path
    angle ``gamma_deg``, for comparisons: tools/maneuver); fold the trim commands into the five
    surface positions.  The leading-edge flap follows :func:`lef_schedule_rad` at the trim's
    alpha (iterated from the flap out), or is held at ``lef_rad`` (the other configuration of a
    point near the flap's switch, for a design: design/schedule.py).  Raises ValueError outside
    the envelope, TrimError if no trim exists."""
    check_flight_condition(mach, alt_ft)
    if lef_rad is not None:
        lef = float(lef_rad)
        _trim_once(fdm, mach, alt_ft, lef, gamma_deg)
    else:
        lef = lef_schedule_rad(0.15, mach)  # first guess: alpha above 5 deg
        for _ in range(3):
            _trim_once(fdm, mach, alt_ft, lef, gamma_deg)
            new_lef = lef_schedule_rad(fdm["aero/alpha-rad"], mach)
            if new_lef == lef:
                break
            lef = new_lef
        lef = fdm["fcs/lef-pos-rad"]  # the flap the aircraft was trimmed with
    e_max, a_max, r_max = actuators.TRIM_COMMAND_SCALE_RAD
    de = e_max * (fdm["fcs/elevator-cmd-norm"] + fdm["fcs/pitch-trim-cmd-norm"])
    da = a_max * (fdm["fcs/aileron-cmd-norm"] + fdm["fcs/roll-trim-cmd-norm"])
    dr = r_max * (fdm["fcs/rudder-cmd-norm"] + fdm["fcs/yaw-trim-cmd-norm"])
    for p in ("elevator", "aileron", "rudder"):
        fdm[f"fcs/{p}-cmd-norm"] = 0.0
    for p in ("pitch", "roll", "yaw"):
        fdm[f"fcs/{p}-trim-cmd-norm"] = 0.0
    u = np.array([de, de, da, -da, dr])
    set_surfaces(fdm, u)
    _store_state_as_ic(fdm)  # its run_ic computes the zeroed command terms once more
    turbulence.hold_axes(fdm)   # its run_ic leaves a round-off mean wind (truth/turbulence.py)
    fdm[TRIM_COMMANDS_PROPERTY] = 0
    lim = np.array(actuators.POSITION_LIMIT_RAD)
    if np.any(np.abs(u) > lim):
        raise TrimError(f"trim at Mach {mach}, {alt_ft:.0f} ft needs surface deflections "
                        f"{np.degrees(u).round(2).tolist()} deg beyond the position limits")
    return TrimPoint(
        u_rad=u, z=sensors.ideal(fdm), throttle=fdm["fcs/throttle-cmd-norm"],
        vt_fps=fdm["velocities/vt-fps"], alpha_rad=fdm["aero/alpha-rad"],
        theta_rad=fdm["attitude/theta-rad"], mach=float(mach), alt_ft=float(alt_ft),
        lef_rad=lef, qbar_psf=fdm["aero/qbar-psf"], weight_lbs=fdm["inertia/weight-lbs"],
    )


def _store_state_as_ic(fdm: jsbsim.FGFDMExec) -> None:
    """Make the trimmed state the initial condition, so ``run_ic()`` returns to the trim."""
    vals = {p: fdm[s] for p, s in (
        ("ic/phi-rad", "attitude/phi-rad"), ("ic/theta-rad", "attitude/theta-rad"),
        ("ic/psi-true-rad", "attitude/psi-rad"), ("ic/u-fps", "velocities/u-fps"),
        ("ic/v-fps", "velocities/v-fps"), ("ic/w-fps", "velocities/w-fps"),
        ("ic/p-rad_sec", "velocities/p-rad_sec"), ("ic/q-rad_sec", "velocities/q-rad_sec"),
        ("ic/r-rad_sec", "velocities/r-rad_sec"), ("ic/h-sl-ft", "position/h-sl-ft"))}
    for p, v in vals.items():  # attitude first: body velocities are set in that attitude
        fdm[p] = v
    fdm.run_ic()


def start_state(fdm) -> dict:
    """What a flight changes that the trimmed initial condition does not hold, as it is right
    after :func:`trim`: the engines' spool speeds ``n1``/``n2`` (%) and fuel flows (lbs/h, which
    the engine model moves towards their target at a limited rate), the fuel in every tank
    (lbs), and the simulation time (s)."""
    props = {}
    for kind, fields in (("engine", ("n1", "n2")), ("tank", ("contents-lbs",))):
        for i in range(64):
            try:
                props.update({f"propulsion/{kind}[{i}]/{f}": fdm[f"propulsion/{kind}[{i}]/{f}"] for f in fields})
            except KeyError:
                break
    return {"properties": props, "fuel_flow_pph": fdm.fuel_flow_pph(), "sim_time_s": fdm.get_sim_time()}


def restart(fdm, trim_point: TrimPoint, start: dict, seed: int) -> None:
    """Return a trimmed ``fdm`` (a ``core.JSBSimExec``) to the state :func:`trim` left, with
    JSBSim's generators seeded by ``seed``, so that a flight from here is the flight of a
    freshly loaded and trimmed aircraft with that seed, bit for bit
    (tests/python/test_truth_setup.py).  ``start`` is :func:`start_state` of the trimmed aircraft.

    The turbulence is switched off (``turbulence.apply`` sets a flight's level afterwards) and
    its filter states zeroed, the generators re-made, the clock, the five surfaces, the engine
    spools and fuel flows and the fuel written back, and the stored trimmed initial condition run
    (``run_ic``: the aircraft's position, attitude and velocities, and the integrators'
    histories), and the turbulence axes fixed with no mean wind (``turbulence.hold_axes``).  The
    engine's other states (running, throttle, nozzle) do not move in level flight at fixed throttle."""
    turbulence.apply(fdm, "none")
    fdm["simulation/randomseed"] = int(seed)
    fdm["atmosphere/randomseed"] = int(seed)
    fdm.reset_winds()
    fdm.set_sim_time(start["sim_time_s"])
    set_surfaces(fdm, trim_point.u_rad)
    for prop, value in start["properties"].items():
        fdm[prop] = value
    fdm.set_fuel_flow_pph(start["fuel_flow_pph"])
    fdm.run_ic()
    turbulence.hold_axes(fdm)


def _trim_once(fdm: jsbsim.FGFDMExec, mach: float, alt_ft: float, lef_rad: float, gamma_deg: float = 0.0) -> None:
    fdm["ic/h-sl-ft"] = alt_ft
    fdm["ic/mach"] = mach
    fdm["ic/gamma-deg"] = gamma_deg
    fdm["ic/phi-deg"] = 0.0
    fdm["ic/beta-deg"] = 0.0
    fdm["ic/psi-true-deg"] = 0.0
    fdm["gear/gear-cmd-norm"] = 0.0
    fdm["gear/gear-pos-norm"] = 0.0
    fdm["fcs/lef-pos-rad"] = lef_rad
    fdm["fcs/throttle-cmd-norm"] = 0.5
    fdm[TRIM_COMMANDS_PROPERTY] = 1
    set_surfaces(fdm, (0.0,) * 5)
    fdm["propulsion/engine[0]/set-running"] = 1
    fdm.run_ic()
    try:
        fdm["simulation/do_simple_trim"] = 1
    except jsbsim.TrimFailureError as exc:
        flight = "level flight" if gamma_deg == 0.0 else f"a {gamma_deg:g} deg flight path"
        raise TrimError(f"JSBSim could not trim the F-16 in {flight} at Mach {mach}, "
                        f"{alt_ft:.0f} ft ({exc})") from None


def trimmed_fdm(mach: float = 0.4, alt_ft: float = 20_000.0, seed: int = 1,
                dt_s: float = 1.0 / SIM_RATE_HZ, lef_rad: float | None = None) -> tuple[jsbsim.FGFDMExec, TrimPoint]:
    """A trimmed derived aircraft at (mach, alt_ft) and its TrimPoint (``lef_rad``: see :func:`trim`).

    The five surface positions are then set with :func:`set_surfaces` (rad, no actuator
    dynamics); read measurements with ``sensors.ideal(fdm)``.
    """
    fdm = load_fdm(seed=seed, dt_s=dt_s)
    return fdm, trim(fdm, mach, alt_ft, lef_rad)
