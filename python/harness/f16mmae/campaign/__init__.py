"""Monte Carlo campaigns of closed-loop runs: planning, executors, results store, scoring,
figures and the HTML report.

* ``single``   -- the single-failure campaign (paper Sec. V, Figs. 3-6);
* ``executor`` -- ``concurrent.futures`` executors: local process pool or a Dask cluster;
* ``store``    -- one JSON-lines record per run, appended as runs finish, resumable;
* ``scoring``  -- correct / missed / wrong isolation, false alarms, detection latency;
* ``figures``  -- the paper-style probability strips and the latency chart;
* ``report``   -- one self-contained HTML page from a campaign or run directory.
"""
