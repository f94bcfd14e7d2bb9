"""Monte Carlo campaigns of closed-loop runs: planning, executors, results store, scoring,
figures and the HTML report.

* ``single``   -- the single-failure campaign (paper Sec. V, Figs. 3-6);
* ``dual``     -- every ordered pair of failures, rated against the lone second failure
  (paper Sec. VI, Fig. 7): ``dual_scoring`` (per run, per pair, the rating),
  ``dual_figures``, ``dual_report``;
* ``envelope`` -- the nominal design flown at the paper's off-nominal points (Sec. VIII,
  Fig. 9): ``envelope_points`` (the points, ISA dynamic pressure), ``envelope_figures``,
  ``envelope_report``;
* ``runner``   -- the loop they share: fly the planned runs not stored yet, store each record;
* ``executor`` -- ``concurrent.futures`` executors: local process pool or a Dask cluster;
* ``store``    -- one JSON-lines record per run, appended as runs finish, resumable;
* ``scoring``  -- correct / missed / wrong isolation, false alarms, detection latency;
* ``figures``  -- the paper-style probability strips and the latency chart;
* ``report``   -- one self-contained HTML page from a campaign (any kind) or run directory.
"""
