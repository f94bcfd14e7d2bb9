"""Filter design (paper Sec. IV-V): from the nonlinear truth to the model-bank file.

- ``linearize``: trim-point linearization of the bare airframe (central differences, and
  JSBSim's FGLinearization as the cross-check);
- ``model``: the 13-state continuous design model (airframe + actuator lags + zero-order
  Dryden gusts + sensors);
- ``discretize``: exact ZOH / Van Loan discretization at the frame rate;
- ``hypotheses``: NONE, 12 single and 66 dual failure models (B column / H row removed);
- ``gains``: DARE -> steady-state K and A = H P- H^T + R (eq. 5), unstable filters refused;
- ``tuning``: pseudonoise methods 1-4 as named knobs from TOML (``tunings/``);
- ``flights``, ``residuals``, ``calibrate``: how the ``tuned`` knobs were measured;
- ``bank``: assemble and write the bank (``design_bank``, ``write_bank``);
- ``report``: the design report (text + figures).

Command line: ``f16mmae design --mach 0.4 --alt-ft 20000 --tuning tuned --out FILE``.
"""
from .bank import BankDesign, design_bank, nominal_bank_path, to_model_bank, write_bank
from .gains import DesignError
from .tuning import Tuning, TuningError, load_tuning

__all__ = ["BankDesign", "design_bank", "nominal_bank_path", "to_model_bank", "write_bank",
           "DesignError", "Tuning", "TuningError", "load_tuning"]
