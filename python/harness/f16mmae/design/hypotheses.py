"""The failure hypotheses of the bank (paper Sec. II-III, Fig. 2) as changes to the
no-failure discrete model ``(Phi, B_d, H)``.

- Actuator failure j: the column j of ``B_d`` is removed (set to zero). The surface no
  longer answers its command; its first-order lag state stays in the model and, with no
  input, decays to zero, i.e. to its TRIM deflection -- the paper's "complete" failure
  (surface held at trim). Zeroing the continuous ``B`` column before discretizing gives
  exactly the same ``B_d`` (the column of ``B_d`` is ``int e^{F s} ds b_j``), so removing
  the discrete column is exact.
- Sensor failure i: the row i of ``H`` is removed (set to zero). The model then expects
  that channel to carry only its noise around the trim value (``z_i - z_trim,i = v_i``).
- A dual hypothesis ``"A+B"`` applies both removals.

``Phi``, ``Q_d`` and ``R`` are the same in every hypothesis.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import names


@dataclass(frozen=True)
class HypothesisModel:
    """The discrete model presumed by one hypothesis (perturbations from trim)."""

    name: str
    phi: np.ndarray  # (nx, nx)
    bd: np.ndarray   # (nx, nu)
    h: np.ndarray    # (nz, nx)


def hypothesis_model(name: str, phi: np.ndarray, bd: np.ndarray, h: np.ndarray) -> HypothesisModel:
    """The model of hypothesis ``name`` (``"NONE"``, ``"LS"``, ``"PIT"``, ``"LS+PIT"``, ...)
    from the no-failure ``(phi, bd, h)``: failed actuators' B_d columns and failed sensors'
    H rows set to zero. Raises ValueError naming an unknown component."""
    bd_k = np.array(bd, dtype=float, copy=True)
    h_k = np.array(h, dtype=float, copy=True)
    for comp in names.failed_components(name):
        if comp in names.ACTUATORS:
            bd_k[:, names.ACTUATORS.index(comp)] = 0.0
        else:
            h_k[names.SENSORS.index(comp), :] = 0.0
    return HypothesisModel(name=name, phi=np.array(phi, dtype=float, copy=True), bd=bd_k, h=h_k)


def all_hypothesis_models(phi: np.ndarray, bd: np.ndarray, h: np.ndarray,
                          hypotheses: tuple[str, ...] = names.ALL_HYPOTHESES) -> list[HypothesisModel]:
    """Models of every hypothesis in bank order: NONE, the 12 singles, the 66 duals."""
    return [hypothesis_model(n, phi, bd, h) for n in hypotheses]
