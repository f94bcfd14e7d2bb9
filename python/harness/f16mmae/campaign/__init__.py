"""Monte Carlo campaigns of closed-loop runs: an engine plus one folder per kind.

* ``engine``   -- what every kind shares: config, seeds, runner, executor, store, scoring;
* ``single``   -- the single-failure campaign (paper Sec. V, Figs. 3-6);
* ``dual``     -- every ordered pair of failures, rated against the lone second failure
  (paper Sec. VI, Fig. 7);
* ``envelope`` -- the nominal design flown at the paper's off-nominal points (Sec. VIII,
  Fig. 9);
* ``detectability`` -- detection probability against bias, drift and loss size (issue 13).

Kinds never import each other; each registers its report page with ``f16mmae.report`` when
imported.  A new kind (soak, maneuver) is one more folder of the same shape.
"""
