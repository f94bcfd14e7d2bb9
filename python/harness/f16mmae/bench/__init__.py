"""Benchmarks behind one front end, ``f16mmae bench estimator|truth|lcm``: the C++ estimator
against Python references (``estimator``), the truth model against bare JSBSim (``truth``),
and the LCM round trip to ``mmae-daemon`` (``lcm``)."""
