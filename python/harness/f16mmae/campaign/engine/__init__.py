"""What every campaign kind shares: the config's shared flight fields (``config``), seeds
(``seeds``), the single-failure runs the single and envelope kinds fly (``failure_runs``),
the loop over planned runs (``runner``), executors (``executor``), the results store
(``store``), scoring primitives (``scoring``) and the progress bar (``progress``)."""
