"""The closed loop: the estimator boundary (``estimator``), one flight (``flight``: ``fly`` and
its ``FlightResult``, data only) and the estimator's cost in the loop (``overhead``)."""
