"""Which code flies the truth model's frames.

Engines (``ENGINES``):

``cpp`` (default)
    The per-step path (sensors, flight control law, dither, actuators, failures) in C++
    (``cpp/truth/truth_frame.h``), stepping JSBSim from C++ (``f16mmae.core.TruthFrames`` over a
    ``core.JSBSimExec``): one Python call per frame, or one per flight (``fly_raw``, and the
    closed loop with the in-process estimator).
``python``
    The reference: the same model in this package's Python (``actuators``, ``sensors``,
    ``fcs``, ``dither``), reading and writing JSBSim's properties from Python.  Slower (about
    2x the C++ engine per flight);
    kept as the readable statement of the model and the yardstick of the C++ path
    (tests/python/test_truth_engines.py flies both and requires the same flights).

Both fly the same JSBSim aircraft, a ``core.JSBSimExec`` (the ``jsbsim`` package's library made
and stepped from C++), set up by the same code (``aircraft``); select with
``TruthModel(scenario, engine=...)`` or the environment variable ``F16MMAE_TRUTH_ENGINE``.

Set-up once per flight condition: ``truth.pool``.
"""
from __future__ import annotations

import os

ENGINES: tuple[str, ...] = ("cpp", "python")
#: Environment variable selecting the default engine.
ENGINE_ENV = "F16MMAE_TRUTH_ENGINE"


def default_engine() -> str:
    """The engine used when none is given: ``$F16MMAE_TRUTH_ENGINE`` or ``cpp``."""
    return check_engine(os.environ.get(ENGINE_ENV, "cpp"))


def check_engine(name: str | None) -> str:
    """``name`` if it is one of ENGINES (None: the default), else ValueError naming them."""
    if name is None:
        return default_engine()
    if name not in ENGINES:
        raise ValueError(f"unknown truth engine {name!r}; valid: {', '.join(ENGINES)}")
    return name


def jsbsim_exec(root_dir: str):
    """A ``core.JSBSimExec`` at ``root_dir``, after checking that the core was built against the
    jsbsim release installed (the C++ path calls into that release's library)."""
    import jsbsim

    from .. import core

    if core.JSBSIM_VERSION != jsbsim.__version__:
        raise RuntimeError(f"f16mmae.core was built against jsbsim {core.JSBSIM_VERSION} but jsbsim "
                           f"{jsbsim.__version__} is installed: rebuild f16mmae (make build) or "
                           f"install jsbsim=={core.JSBSIM_VERSION}")
    return core.JSBSimExec(root_dir)
