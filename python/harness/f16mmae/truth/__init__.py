"""The truth model (issue 3): JSBSim's F-16 airframe with our mixer, five failable actuators
(LS RS LF RF RUD), seven failable sensors (VEL AOA PIT AZ ROL YAW AY), MIL-F-8785C Dryden
turbulence, a Block-40-style FCS, dither and failure injection.  Contract: docs/INTERFACES.md.

Modules: ``aircraft`` (derived aircraft, trim, restart, direct surface access), ``actuators``,
``sensors``, ``turbulence``, ``fcs``, ``dither``, ``failures``, ``scenario``, ``model``
(TruthModel), ``engine`` (the C++ per-step path or the Python reference), ``pool`` (one trimmed
aircraft per flight condition and process).  The per-step arithmetic's C++ twin is
cpp/truth/truth_frame.h.  Rates: JSBSim at SIM_RATE_HZ = 128, FCS/sensors at FRAME_RATE_HZ = 64.
"""
from .aircraft import TrimError, TrimPoint, trimmed_fdm
from .dither import DitherSpec
from .failures import FailureSpec, make_failure, parse_fail, parse_fail_args, parse_failure
from .fcs import FcsGains, FlightControlSystem
from .model import TruthModel, fly_raw
from .scenario import Scenario

__all__ = ["TrimError", "TrimPoint", "trimmed_fdm", "DitherSpec", "FailureSpec", "make_failure", "parse_fail", "parse_failure",
           "parse_fail_args", "FcsGains", "FlightControlSystem", "TruthModel", "fly_raw", "Scenario"]
