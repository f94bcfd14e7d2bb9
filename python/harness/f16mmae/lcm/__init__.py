"""The LCM edge of the harness: channel names (``channels``), frames on the wire (``codec``),
the ``mmae-daemon`` process (``daemon``), the executive as a remote estimator (``remote``),
HIL flights against it (``hil``) and the replay of recorded traffic (``replay``)."""
