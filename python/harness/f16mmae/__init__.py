"""f16mmae: multiple model adaptive estimation (MMAE) failure detection for the F-16.

Implements Eide & Maybeck, "An MMAE Failure Detection System for the F-16": a bank of
steady-state Kalman filters (C++ core, ``f16mmae.core``), a nonlinear JSBSim truth model
(``f16mmae.truth``), the filter design pipeline (``f16mmae.design``) and closed-loop
Monte Carlo campaigns.  The compiled core is imported lazily so the pure-Python parts
work on their own.
"""
from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("f16mmae")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"


def _bind_lcm_types() -> None:
    """Bind the lcm-gen message classes (``lcmt_*``, built from ``lcm_types/``) onto the package.

    lcm-gen's generated modules refer to nested types as ``f16mmae.lcmt_x`` *classes*, as its
    own ``__init__.py`` would bind them; this package has its own ``__init__``, so it does
    the same here (a few tiny modules, present once the package is built).
    """
    import importlib
    import pkgutil

    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("lcmt_"):
            module = importlib.import_module(f"{__name__}.{info.name}")
            globals()[info.name] = getattr(module, info.name)


_bind_lcm_types()
