"""The ``f16mmae`` command line: ``main`` and one module per command, each with
``register(subparsers)``, which adds the command's parser (with a ``--help`` that teaches) and
sets ``func(args) -> int`` on it: the process exit code."""
